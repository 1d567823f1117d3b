//! The command line (clap): subcommands, their options and help texts.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
pub(crate) use wedged_cli::jobs::{CriticalMethodArg, MethodArg};

pub(crate) const EXIT_CODES: &str = "\
Exit codes:
  0  the run completed, whether or not wedged configurations exist
  1  internal failure (e.g. a computed ray failed verification; a bug)
  2  bad input or usage (unreadable or invalid problem file, bad option, unwritable --json path)
  3  the run is incomplete: it stopped early (--time-limit, --max-rays, --max-memory, Ctrl-C), or
     the conic solver could not decide some contact sets (pattern methods; the summary warns
     about each). The summary and the JSON say so (\"complete\": false); what was not finished
     is neither claimed nor ruled out";

pub(crate) const PROBLEM_FILE: &str = "\
Problem file (TOML), a condensed stiffness:
  dim = 2                      # space dimension, 2 or 3 (3: sign patterns, --method bnb)
  mu = 0.8                     # friction coefficient, > 0
  [stiffness]                  # K on the contact nodes, local frames, normal first
                               #   (2D: n, t per node; 3D: n, t1, t2)
  matrix_market = \"K.mtx\"      # relative to the TOML file's directory, or:
  # rows = [[2.0, 1.0], [1.0, 1.0]]
  # rigid_modes = \"R.mtx\"      # a floating body (K singular): its free rigid motions,
                               #   dim*m x k, same frames, K R = 0 (a file or rows)

or a meshed body, condensed onto its contact nodes:
  mu = 0.8
  [mesh]
  gmsh = \"plug.msh\"            # Gmsh MSH 4.1 or 2.2 (ASCII or binary), groups by name, or
                               #   a Gmsh script (.geo, meshed by Gmsh at each run), with:
  # size_factor = 2            #   every mesh size of the script times this (-clscale)
  # [mesh.parameters]          #   its DefineConstant numbers (half_angle = 20, ...); or
  # [mesh.generate]            # a built-in body:
  # kind = \"plug2d\"            #   bottom_width, top_width, height, nx, ny, element = quad|tri
  #                            # 3D: vgroove3d: bottom_width, top_width, height, length, nx,
  #                            #   ny, nz, element = hex|tet;  frustum3d: bottom_width,
  #                            #   top_width, height, n, nz, element = hex|tet
  [material]
  young = 210e9
  poisson = 0.3
  plane = \"strain\"             # 2D: strain | stress
  [[contact]]                  # contact candidates against a rigid obstacle along the surface
  group = \"contact\"            # optional: normal = [nx, ny(, nz)], the body's inward normal
  [[clamp]]                    # zero displacement (none: the body floats, held by the
  group = \"top\"                #   walls alone; its pieces are then sign patterns)
  # [[symmetry]]               # roller: zero displacement along the group's normal
  # group = \"axis\"";

pub(crate) const CRITICAL_HELP: &str = "\
The critical friction coefficient mu* is the least friction coefficient at which the body can stay
wedged (a nontrivial equilibrium without load). It is reported as a bracket [lower, upper]: a
wedged configuration exists at upper (checked against the wedged problem; mu* = upper), and none
exists below lower (certified by checked infeasibility certificates of the conic solver). The
width actually certified normally reaches --tol; where it cannot (now and then in 3D), it stops
at about 1e-7 relative (the solver's resolution), and the summary says so. \"never\"
(certified: no friction coefficient wedges the body) is a result, exit code 0. The problem
file's mu is not needed; --method enumerate starts its enumeration there (or at 1) and doubles
it until something wedges.";

/// Enumerate the wedged configurations of an elastic body in frictional contact with a rigid
/// obstacle: every equilibrium without load in which the body stays deformed.
#[derive(Debug, Parser)]
#[command(name = "wedged", version, after_help = EXIT_CODES)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Enumerate the wedged configurations of the problem in a TOML file.
    #[command(after_help = EXIT_CODES, after_long_help = format!("{PROBLEM_FILE}\n\n{EXIT_CODES}"))]
    Enumerate(EnumerateArgs),
    /// Condense a meshed body onto its contact nodes and export the stiffness (Matrix Market).
    #[command(after_help = EXIT_CODES, after_long_help = format!("{PROBLEM_FILE}\n\n{EXIT_CODES}"))]
    Condense(CondenseArgs),
    /// Compute the critical friction coefficient mu*: the least mu at which the body can stay
    /// wedged, with a certified bracket and a wedged configuration at its upper end.
    #[command(
        after_help = EXIT_CODES,
        after_long_help = format!("{CRITICAL_HELP}\n\n{PROBLEM_FILE}\n\n{EXIT_CODES}")
    )]
    Critical(CriticalArgs),
    /// Plot how many maximal patterns are realised against mu: each pattern's own threshold
    /// (from the enumeration at a large mu), and mu*, the least of them.
    #[command(
        after_help = EXIT_CODES,
        after_long_help = format!("{CRITICAL_HELP}\n\n{PROBLEM_FILE}\n\n{EXIT_CODES}")
    )]
    Sweep(SweepArgs),
    /// The critical friction coefficient over a grid of the problem file's parameters
    /// (notch half-angle, Poisson's ratio, mesh refinement, any number in the file): a CSV, a
    /// plot and, for mesh studies, the limit h -> 0; resumable
    #[command(
        after_help = EXIT_CODES,
        after_long_help = format!("{STUDY_HELP}\n\n{CRITICAL_HELP}\n\n{EXIT_CODES}")
    )]
    Study(StudyArgs),
    /// Run the built-in example: a 2D plug wedged in a V-notch, with JSON, VTU and SVG output,
    /// and its critical friction coefficient.
    #[command(after_help = EXIT_CODES)]
    Demo(DemoArgs),
    /// Merge the parts of a sharded run (`enumerate` or `critical` with `--shard I/N --json
    /// PART`) into the JSON one run writes; a missing shard is named and the merge is then
    /// marked incomplete (exit 3).
    #[command(after_help = EXIT_CODES)]
    Merge(MergeArgs),
}

#[derive(Debug, Args)]
pub(crate) struct CriticalArgs {
    /// The problem file (TOML; see --help for its format; its `mu` is optional).
    pub(crate) problem: PathBuf,
    /// Algorithm [default: bnb].
    #[arg(long, value_name = "METHOD")]
    pub(crate) method: Option<CriticalMethodArg>,
    /// Re-check the answer in exact rational arithmetic: every infeasibility certificate behind
    /// `lower` and the witness at `upper` (bnb and faces; enumerate's lower end rests on a
    /// floating-point enumeration and is reported as not certified). Exit code 1 if a check
    /// fails.
    #[arg(long)]
    pub(crate) certify: bool,
    #[command(flatten)]
    pub(crate) common: CriticalCommon,
    #[command(flatten)]
    pub(crate) json: JsonArg,
    /// Run shard I of N of the bnb search only, and write it with --json as a part for
    /// `wedged merge`, which gives the one-run bracket (see `enumerate --shard`).
    #[arg(long, value_name = "I/N", value_parser = wedged::Shard::parse)]
    pub(crate) shard: Option<wedged::Shard>,
    /// Start the bnb search from the wedged configuration of an earlier `critical --json`
    /// result, such as the same body on a coarser mesh (its contact pattern mapped to this
    /// mesh's contact nodes by position, on the same face): a first upper end near mu* at
    /// once, where the search's own first leaf can be far above on a fine mesh. The bracket does
    /// not depend on it. Not used with --certify or --shard.
    #[arg(long, value_name = "PREVIOUS.json")]
    pub(crate) start: Option<PathBuf>,
    /// Compute from scratch. By default a problem of 80 contact nodes or more in 2D, 40 in 3D,
    /// is first solved condensed onto about half its nodes (itself so, while large enough), and
    /// the search starts from that wedge as --start would; the bracket does not depend on it
    #[arg(long)]
    pub(crate) no_chain: bool,
}

#[derive(Debug, Args)]
pub(crate) struct SweepArgs {
    /// The problem file (TOML; see --help for its format; its `mu`, when given, is where the
    /// enumeration starts).
    pub(crate) problem: PathBuf,
    /// Write the step plot here (SVG, written atomically).
    #[arg(long, value_name = "PLOT.svg")]
    pub(crate) svg: PathBuf,
    /// Also write each pattern's configuration at its own threshold as DIR/threshold-N.vtu
    /// (meshed problems) and DIR/sweep.pvd, their ParaView collection with mu as the time
    #[arg(long, value_name = "DIR")]
    pub(crate) vtk: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) common: CriticalCommon,
    #[command(flatten)]
    pub(crate) json: JsonArg,
}

/// The options that `critical` and `sweep` share.
pub(crate) const STUDY_HELP: &str = "\
A study computes mu* at every point of a grid and writes DIR/study.csv (one row per point,
rewritten after each point), DIR/study.svg (mu* against --x, a line per combination of the
other parameters) and, with --vtk, DIR/point-N.vtu (the witness at mu* of point N) and
DIR/study.pvd (their ParaView collection). Run the same command again to resume: complete
points are read back from study.csv; incomplete ones (a time limit, Ctrl-C) are computed again.

--vary KEY=V1,V2,... or KEY=FROM:TO:COUNT, repeated for a grid (every combination). KEY is a
number the problem file sets, dotted: material.poisson, mesh.generate.ny (varying mu only
moves where the search starts: mu* does not depend on it). Two derived keys for a generated body ([mesh.generate]):
  half_angle   the notch half-angle in degrees from the vertical: sets top_width =
               bottom_width + 2 height tan(half_angle)
  refine       a whole factor multiplying its division counts (nx, ny, nz, n)
With refine (or a division count) first, the plot is against the mesh size h, and the
summary extrapolates mu* to h = 0 (Richardson, through the three finest meshes), or says
that it grows like ln(1/h) (no finite limit) when that is what the three finest show. A
Gmsh script's mesh size does the same when it is varied first with --x h:
  wedged study plug.toml --vary mesh.parameters.lc=0.2,0.1,0.07,0.05 --x h --out sizes

  wedged study examples/plug2d.toml --vary refine=1,2,3,4 --out plug-study
  wedged study examples/plug2d.toml --vary half_angle=15:45:7 --vary material.poisson=0.2,0.3 \\
      --out angles --time-limit 60";

#[derive(Debug, Args)]
pub(crate) struct StudyArgs {
    /// Problem file (TOML) whose numbers the study varies
    pub(crate) problem: PathBuf,
    /// KEY=V1,V2,... or KEY=FROM:TO:COUNT (COUNT values, both ends included); repeat for a
    /// grid. See --help for the keys
    #[arg(long = "vary", value_name = "KEY=VALUES", required = true,
          value_parser = wedged_cli::study::parse_vary)]
    pub(crate) vary: Vec<wedged_cli::study::Parameter>,
    /// Output directory (created): study.csv, study.svg, and with --vtk point-N.vtu and
    /// study.pvd
    #[arg(long, value_name = "DIR")]
    pub(crate) out: PathBuf,
    /// The plot's x axis: one of the varied keys, or h (the mesh size). Default: h when the
    /// first varied key refines the mesh, else the first varied key
    #[arg(long = "x", value_name = "KEY")]
    pub(crate) x: Option<String>,
    /// Also write each point's witness as DIR/point-N.vtu and their collection DIR/study.pvd
    #[arg(long)]
    pub(crate) vtk: bool,
    /// Search method at each point: bnb (default), enumerate or faces
    #[arg(long, value_name = "METHOD")]
    pub(crate) method: Option<CriticalMethodArg>,
    /// Certify each point's bracket exactly (as `critical --certify`)
    #[arg(long)]
    pub(crate) certify: bool,
    /// Compute every point from scratch. By default a point on a finer mesh (a refining key
    /// changed, the others the same) starts its search from the answer of the last such point
    /// computed, as `critical --start` does, and any other point of 80 contact nodes or more
    /// (40 in 3D) from its problem condensed onto about half its nodes, as `critical` does; the
    /// brackets do not depend on it
    #[arg(long)]
    pub(crate) no_chain: bool,
    /// --tol as for `critical`; --time-limit applies to each point
    #[command(flatten)]
    pub(crate) common: CriticalCommon,
}

#[derive(Debug, Args)]
pub(crate) struct CriticalCommon {
    /// Relative width asked of the bracket of mu*, from 1e-12 to 0.1 [default: 1e-9].
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub(crate) tol: Option<f64>,
    /// Stop after this many seconds (the result is then marked incomplete; exit code 3).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub(crate) time_limit: Option<f64>,
}

#[derive(Debug, Args)]
pub(crate) struct EnumerateArgs {
    /// The problem file (TOML; see --help for its format).
    pub(crate) problem: PathBuf,
    /// Friction coefficient, overriding the file's `mu`.
    #[arg(long, value_name = "MU", allow_negative_numbers = true)]
    pub(crate) mu: Option<f64>,
    /// Algorithm [default: search (the rays) for a 2D problem of up to 12 contact nodes,
    /// pruned-dd there with --max-rays or --max-memory; pattern-search for a larger one (its extreme rays are out of reach there: the pieces
    /// with a witness each instead; bnb with --certify), for a floating body, with --shard or
    /// --jsonl; bnb for a 3D one]. The ray methods
    /// (pruned-dd, full-dd, faces, exact, search) list the complementary extreme rays and the
    /// cones of a 2D problem; the pattern methods (bnb, pyramid, pattern-faces, pattern-search) list the maximal sign patterns
    /// (the convex pieces, each with a witness) of a 2D or 3D problem.
    #[arg(long, value_name = "METHOD")]
    pub(crate) method: Option<MethodArg>,
    /// Faces of the pyramid that replaces the round friction cone in --method pyramid, 3 to 64
    /// [default: 8]. Only --method pyramid uses it (and only in 3D).
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    pub(crate) pyramid_faces: Option<i64>,
    /// Relative zero tolerance of the enumeration [default: 1e-9].
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub(crate) zero_tol: Option<f64>,
    /// Stop after this many seconds (the result is then marked incomplete; exit code 3).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub(crate) time_limit: Option<f64>,
    /// Stop when more than this many rays would be held at once (a memory bound: a ray of an
    /// m-node problem takes about 16 m bytes; ray methods and pyramid); the result is then
    /// marked incomplete.
    #[arg(long, value_name = "N")]
    pub(crate) max_rays: Option<usize>,
    /// Stop when the rays held would take more than this much memory: bytes, or with a unit
    /// (500M, 2G, 1.5GB; powers of 1000; ray methods and pyramid); the result is then marked
    /// incomplete.
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    pub(crate) max_memory: Option<u64>,
    #[command(flatten)]
    pub(crate) json: JsonArg,
    /// Stream the pieces: write each maximal sign pattern to this file as one line of JSON
    /// (pattern, status, u, r, margin, as in --json) as soon as it is found, and keep none in
    /// memory. pattern-search (the default with --jsonl in 2D) writes each one as its leaf of
    /// the search is decided, in the order found, so memory does not grow with the number of
    /// pieces; bnb (3D) writes each orbit of pieces under the mesh's symmetries as its first
    /// leaf is decided (pieces with grazing nodes at the end), holding a few bytes per orbit;
    /// the other pattern methods write theirs at the end. The summary and --json then
    /// give the count, not the pieces. A run that stops early has written the pieces found so
    /// far. `-` streams to stdout, which then holds the lines only (no summary). Not with a ray
    /// method, --vtk, --svg or --shard.
    #[arg(long, value_name = "OUT.jsonl")]
    pub(crate) jsonl: Option<PathBuf>,
    /// For a meshed body: write one ParaView file per wedged cone, DIR/cone-N.vtu, or with a
    /// pattern method per maximal pattern, DIR/pattern-N.vtu (old cone-N.vtu and pattern-N.vtu
    /// files in DIR are removed).
    #[arg(long, value_name = "DIR")]
    pub(crate) vtk: Option<PathBuf>,
    /// For a meshed body: write one picture per wedged cone, DIR/cone-N.svg, or with a pattern
    /// method per maximal pattern, DIR/pattern-N.svg (old cone-N.svg and pattern-N.svg files in
    /// DIR are removed).
    #[arg(long, value_name = "DIR")]
    pub(crate) svg: Option<PathBuf>,
    /// Certify the answer in exact rational arithmetic. A 2D ray method (pruned-dd, full-dd,
    /// faces, exact): each ray recomputed from its status, checked extreme, feasible with
    /// exactly its status and complementary, and compared with the floating-point ray; each
    /// cone's rays checked cross-complementary (completeness checked up to 8 nodes; --exact
    /// gives a provably complete answer). A pattern method (bnb, pattern-faces, pattern-search; 2D or 3D): each
    /// pattern's witness recomputed exactly and checked, and every decision of the search
    /// backed by an infeasibility certificate checked exactly, which proves the patterns are
    /// all the maximal ones (pyramid cannot be certified: refused). A failure is
    /// reported and the exit code is 1.
    #[arg(long)]
    pub(crate) certify: bool,
    /// Run the whole 2D enumeration in exact rational arithmetic (the same as --method exact):
    /// K and mu taken as the rationals their f64s are, every sign decided exactly, so the rays,
    /// their statuses and the cones are provably all of them. Slower than pruned-dd.
    #[arg(long)]
    pub(crate) exact: bool,
    /// Run shard I of N of the search only, and write it with --json as a part for `wedged
    /// merge` (a cluster job array: one shard per task; see examples/slurm). Every shard
    /// computes the same split, so the parts need no other coordination. Splits the search of
    /// --method bnb or pattern-search (the default with --shard in 2D).
    #[arg(long, value_name = "I/N", value_parser = wedged::Shard::parse)]
    pub(crate) shard: Option<wedged::Shard>,
}

#[derive(Debug, Args)]
pub(crate) struct MergeArgs {
    /// The parts: the JSON files of `wedged enumerate FILE --shard I/N --json PART` (or of
    /// `wedged critical`), one per shard.
    #[arg(required = true, value_name = "PART.json")]
    pub(crate) parts: Vec<PathBuf>,
    #[command(flatten)]
    pub(crate) json: JsonArg,
}

#[derive(Debug, Args)]
pub(crate) struct CondenseArgs {
    /// The problem file (TOML with a mesh table; see --help).
    pub(crate) problem: PathBuf,
    /// Write the condensed stiffness here (Matrix Market, coordinate real symmetric; written
    /// atomically). Its comment lines name each contact node's mesh node and frame.
    #[arg(long, value_name = "K.mtx")]
    pub(crate) mtx: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub(crate) struct DemoArgs {
    /// Directory for the demo's JSON, VTU and SVG files.
    #[arg(long, value_name = "DIR", default_value = "wedged-demo")]
    pub(crate) out: PathBuf,
    /// The floating cork instead: the same plug with nothing clamped, held by the notch walls
    /// alone (its sign patterns at mu = 0.8, and its mu*, the equilibrium bound 0.5).
    #[arg(long)]
    pub(crate) cork: bool,
}

#[derive(Debug, Args)]
pub(crate) struct JsonArg {
    /// Also write the full result as JSON to this file (written atomically); `-` writes the JSON
    /// to stdout instead of the summary.
    #[arg(long, value_name = "OUT.json")]
    pub(crate) json: Option<PathBuf>,
}

/// A memory size: a number of bytes, or a number with `k`, `M`, `G` or `T` (powers of 1000),
/// optionally followed by `B`: `500M`, `2G`, `1.5GB`.
pub(crate) fn parse_size(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let t = t.strip_suffix(['B', 'b']).unwrap_or(t);
    let (number, factor) = match t.chars().last() {
        Some('k' | 'K') => (&t[..t.len() - 1], 1e3),
        Some('m' | 'M') => (&t[..t.len() - 1], 1e6),
        Some('g' | 'G') => (&t[..t.len() - 1], 1e9),
        Some('t' | 'T') => (&t[..t.len() - 1], 1e12),
        _ => (t, 1.0),
    };
    match number.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 && x * factor < 1.8e19 => Ok((x * factor) as u64),
        _ => Err(format!(
            "expected a positive size such as 500M, 2G or 1500000000, got {text:?}"
        )),
    }
}
