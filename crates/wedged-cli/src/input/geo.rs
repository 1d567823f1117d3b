//! A Gmsh script (`gmsh = "body.geo"`) meshed by Gmsh at each load, with the problem file's
//! `[mesh.parameters]` passed to it: the template of a parameter study (`wedged study --vary
//! mesh.parameters.half_angle=...`), as the built-in bodies are for theirs.
//!
//! Gmsh runs as a separate program: `$WEDGED_GMSH` if set, else `gmsh` on the `PATH` (Gmsh 4;
//! `pip install gmsh` installs one). The command is
//!
//! ```text
//! gmsh body.geo CHECK.geo -3 -format msh41 -o MESH.msh -setnumber NAME VALUE ... [-clscale F] -v 3
//! ```
//!
//! in a temporary directory: `-3` meshes every dimension up to the script's highest (a 2D
//! script gives its 2D mesh), and `-setnumber` sets each parameter before the script runs, so
//! the script must take it with `DefineConstant[ NAME = {DEFAULT} ];` (a plain `NAME = ...;`
//! would overwrite it). The second script, `CHECK.geo`, written here, prints each parameter's
//! value after `body.geo` has run: a parameter that the script overwrote is an error that says
//! so, rather than a study whose points all mesh the same body. So is one that the script
//! never defines, found by a first run that only parses (`-parse_and_exit`, without the
//! parameters, each one's `Exists` printed). Gmsh exits with status 0 after errors in a
//! script; its output is read for them (`Error :` lines), and the first is the message.
//!
//! `size_factor = F` in `[mesh]` multiplies every mesh size of the script by `F` (`-clscale`,
//! Gmsh's `Mesh.MeshSizeFactor`, read back like a parameter): any script's mesh made coarser or
//! finer without a parameter of its own for it. `critical`'s coarser start doubles it
//! (`input/start.rs`), and `study --vary refine=1,2,4` divides it.
//!
//! The mesh is then read as any MSH file ([`super::msh`]).

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::io::ErrorKind;
use std::path::Path;
use std::process::Command;

use wedged::fe::Mesh;

use super::msh;

/// The environment variable that names the Gmsh program.
pub const GMSH_VARIABLE: &str = "WEDGED_GMSH";

/// The prefix of the lines of the check script.
const MARK: &str = "wedged-parameter";

/// The name under which the check script prints Gmsh's `Mesh.MeshSizeFactor`.
const FACTOR: &str = "Mesh.MeshSizeFactor";

/// Meshes the script at `path` with `parameters` and every mesh size times `size_factor`, by
/// Gmsh. `Err` is one line without the problem file's name.
pub fn mesh(
    path: &Path,
    parameters: &BTreeMap<String, f64>,
    size_factor: Option<f64>,
) -> Result<Mesh, String> {
    let shown = path.display();
    if let Some(f) = size_factor.filter(|f| !(f.is_finite() && *f > 0.0)) {
        return Err(format!(
            "[mesh]: size_factor = {f} is not a positive number"
        ));
    }
    if !path.is_file() {
        return Err(format!("cannot read the Gmsh script {shown}: no such file"));
    }
    for (name, value) in parameters {
        let plain = name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
            && name.chars().next().is_some_and(|c| !c.is_ascii_digit());
        if !plain {
            return Err(format!(
                "[mesh.parameters]: `{name}` is not a Gmsh variable name (letters, digits, _)"
            ));
        }
        if !value.is_finite() {
            return Err(format!("[mesh.parameters]: {name} = {value} is not finite"));
        }
    }
    let dir = tempfile::tempdir()
        .map_err(|e| format!("cannot make a temporary directory for Gmsh's mesh: {e}"))?;
    let program = std::env::var_os(GMSH_VARIABLE).unwrap_or_else(|| OsString::from("gmsh"));
    let gmsh = |scripts: &[&Path], args: &[OsString]| run(&program, path, scripts, args);

    // The parameters the script defines: `-setnumber` defines any name, so a name the script
    // never uses would pass the check below unnoticed. A parse without them tells.
    if !parameters.is_empty() {
        let exists = dir.path().join("exists.geo");
        let lines: String = parameters
            .keys()
            .map(|name| {
                format!("If (!Exists({name})) Printf(\"{MARK} {name} undefined\"); EndIf\n")
            })
            .collect();
        std::fs::write(&exists, lines)
            .map_err(|e| format!("cannot write Gmsh's check script: {e}"))?;
        let text = gmsh(&[path, &exists], &["-parse_and_exit".into()])?;
        if let Some(name) = text
            .lines()
            .find_map(|l| l.strip_prefix(MARK)?.trim().strip_suffix("undefined"))
        {
            let name = name.trim();
            return Err(format!(
                "[mesh.parameters]: {shown} has no variable {name}; take it with \
                 `DefineConstant[ {name} = {{...}} ];`"
            ));
        }
    }

    let check = dir.path().join("check.geo");
    let out = dir.path().join("mesh.msh");
    let mut lines: String = parameters
        .keys()
        .map(|name| format!("Printf(\"{MARK} {name} %.17g\", {name});\n"))
        .collect();
    if size_factor.is_some() {
        lines += &format!("Printf(\"{MARK} {FACTOR} %.17g\", {FACTOR});\n");
    }
    std::fs::write(&check, lines).map_err(|e| format!("cannot write Gmsh's check script: {e}"))?;
    let mut args: Vec<OsString> = ["-3", "-format", "msh41", "-o"].map(OsString::from).into();
    args.push(out.clone().into_os_string());
    for (name, value) in parameters {
        args.extend([
            "-setnumber".into(),
            name.into(),
            format!("{value:e}").into(),
        ]);
    }
    if let Some(f) = size_factor {
        args.extend(["-clscale".into(), format!("{f:e}").into()]);
    }
    let text = gmsh(&[path, &check], &args)?;
    check_parameters(&text, parameters, &shown.to_string())?;
    if let Some(f) = size_factor {
        check_factor(&text, f, &shown.to_string())?;
    }
    let bytes = std::fs::read(&out)
        .map_err(|_| format!("Gmsh wrote no mesh for {shown} (does the script define a body?)"))?;
    msh::parse(&bytes, &format!("the mesh of {shown}")).map_err(|e| e.to_string())
}

/// Runs Gmsh (`program`) on `scripts` (`script` first, the one named in messages) with
/// `args` and `-v 3` (errors, warnings and the scripts' `Printf`): its output, or the first
/// error it reports (Gmsh exits with status 0 after errors in a script).
fn run(
    program: &OsString,
    script: &Path,
    scripts: &[&Path],
    args: &[OsString],
) -> Result<String, String> {
    let shown = script.display();
    let output = Command::new(program)
        .args(scripts)
        .args(args)
        .args(["-v", "3"])
        .output()
        .map_err(|e| {
            let program = program.to_string_lossy();
            if e.kind() == ErrorKind::NotFound {
                format!(
                    "meshing {shown} needs Gmsh, and `{program}` was not found: install Gmsh 4 \
                     (`pip install gmsh` is one way) or set {GMSH_VARIABLE} to the program"
                )
            } else {
                format!("cannot run Gmsh (`{program}`) to mesh {shown}: {e}")
            }
        })?;
    let text = String::from_utf8_lossy(&output.stdout).into_owned()
        + &String::from_utf8_lossy(&output.stderr);
    if let Some(error) = text.lines().find(|l| l.starts_with("Error")) {
        let error = error.split_once(':').map_or(error, |(_, e)| e).trim();
        return Err(format!("Gmsh failed on {shown}: {error}"));
    }
    if !output.status.success() {
        let last = text.lines().rev().find(|l| !l.trim().is_empty());
        return Err(format!(
            "Gmsh failed on {shown} ({}){}",
            output.status,
            last.map_or(String::new(), |l| format!(": {}", l.trim()))
        ));
    }
    Ok(text)
}

/// Each parameter's value as the check script printed it after the script ran: as given, or
/// an error naming it.
fn check_parameters(
    text: &str,
    parameters: &BTreeMap<String, f64>,
    script: &str,
) -> Result<(), String> {
    let printed: BTreeMap<&str, f64> = text
        .lines()
        .filter_map(|l| {
            let mut fields = l.strip_prefix(MARK)?.split_whitespace();
            Some((fields.next()?, fields.next()?.parse().ok()?))
        })
        .collect();
    for (name, &value) in parameters {
        match printed.get(name.as_str()) {
            None => {
                return Err(format!(
                    "[mesh.parameters]: Gmsh printed no value of {name} after {script} ran \
                     (is the Gmsh program Gmsh 4?)"
                ))
            }
            Some(&seen) if (seen - value).abs() > 1e-14 * value.abs() => {
                return Err(format!(
                    "[mesh.parameters]: {name} = {value}, but {script} set it to {seen}: \
                     take it with `DefineConstant[ {name} = {{{seen}}} ];` so that the \
                     value given wins"
                ))
            }
            Some(_) => {}
        }
    }
    Ok(())
}

/// The mesh size factor as the check script printed it: as given, or an error (a script that
/// sets `Mesh.MeshSizeFactor` itself ignores `size_factor`).
fn check_factor(text: &str, factor: f64, script: &str) -> Result<(), String> {
    let seen = text.lines().find_map(|l| {
        let mut fields = l.strip_prefix(MARK)?.split_whitespace();
        (fields.next()? == FACTOR).then_some(())?;
        fields.next()?.parse::<f64>().ok()
    });
    match seen {
        None => Err(format!(
            "[mesh]: Gmsh printed no {FACTOR} after {script} ran (is the Gmsh program Gmsh 4?)"
        )),
        Some(seen) if (seen - factor).abs() > 1e-14 * factor => Err(format!(
            "[mesh]: size_factor = {factor}, but {script} sets {FACTOR} = {seen} itself: \
             remove that line so that size_factor applies"
        )),
        Some(_) => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn printed_parameters_are_checked() {
        let given: BTreeMap<String, f64> =
            [("lc".to_string(), 0.2), ("angle".to_string(), 10.0)].into();
        let ok =
            "Warning : x\nwedged-parameter angle 10\nwedged-parameter lc 0.20000000000000001\n";
        assert!(check_parameters(ok, &given, "p.geo").is_ok());
        let overwritten = "wedged-parameter angle 10\nwedged-parameter lc 0.10000000000000001\n";
        let e = check_parameters(overwritten, &given, "p.geo").unwrap_err();
        assert!(
            e.contains(
                "lc = 0.2, but p.geo set it to 0.1: take it with `DefineConstant[ lc = {0.1} ];`"
            ),
            "{e}"
        );
        let e = check_parameters("wedged-parameter lc 0.2\n", &given, "p.geo").unwrap_err();
        assert!(e.contains("printed no value of angle"), "{e}");
    }

    #[test]
    fn the_printed_size_factor_is_checked() {
        let printed = |f: &str| format!("Info : x\nwedged-parameter Mesh.MeshSizeFactor {f}\n");
        assert!(check_factor(&printed("2"), 2.0, "p.geo").is_ok());
        assert!(check_factor(&printed("0.5"), 0.5, "p.geo").is_ok());
        let e = check_factor(&printed("1"), 2.0, "p.geo").unwrap_err();
        assert!(
            e.contains("size_factor = 2, but p.geo sets Mesh.MeshSizeFactor = 1 itself"),
            "{e}"
        );
        let e = check_factor("wedged-parameter lc 2\n", 2.0, "p.geo").unwrap_err();
        assert!(e.contains("printed no Mesh.MeshSizeFactor"), "{e}");
    }
}
