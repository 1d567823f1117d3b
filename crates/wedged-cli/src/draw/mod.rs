//! The pictures and ParaView files of a run: per piece, a VTU file ([`vtk`]) and an SVG
//! picture ([`svg`]), written by [`export`]; the step plot of `sweep` ([`sweep_svg`]); the plot
//! of `study` ([`study_svg`]).

pub mod export;
pub mod study_svg;
pub mod svg;
pub mod sweep_svg;
pub mod vtk;
