//! The readers of the files a user gives: the TOML problem file ([`problem_file`]), Matrix
//! Market stiffness files ([`mtx`], also the writer of `condense`), Gmsh MSH 4.1 and 2.2 meshes
//! ([`msh`]), Gmsh scripts meshed by Gmsh with the problem file's parameters ([`geo`]), and an
//! earlier result that `critical --start` starts from ([`start`]). Each error is one line that
//! names the file (and the line, where there is one).

pub mod geo;
pub mod msh;
pub mod mtx;
pub mod problem_file;
pub mod start;
