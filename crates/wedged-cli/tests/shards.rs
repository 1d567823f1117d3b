//! Shards end to end (issue 24): `wedged enumerate --shard I/N --json PART` for every `I`, then
//! `wedged merge`, writes the JSON of one run (all but `info`, whose counters are the shards'
//! sums, and the model's condensation time), on a 2D mesh (pattern-search), a 3D mesh (bnb)
//! and a floating body; a lost shard is named and the merge marked incomplete (exit 3); a part
//! of another run, a repeated shard, a whole run's JSON, and shards of methods without a
//! search tree are refused (exit 2).

mod common;

use std::path::{Path, PathBuf};

use common::{assert_bad_input, assert_code, example, text, wedged};
use serde_json::Value;

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The document without what may differ between runs: `info` and the condensation's time.
fn answer(mut doc: Value) -> Value {
    let map = doc.as_object_mut().unwrap();
    map.remove("info");
    if let Some(Value::Object(model)) = map.get_mut("model") {
        model.remove("seconds_condense");
    }
    doc
}

/// Runs the `count` shards of `problem` (with `extra` arguments) into `dir`; their paths.
fn shards(dir: &Path, problem: &str, count: usize, extra: &[&str]) -> Vec<PathBuf> {
    (1..=count)
        .map(|i| {
            let part = dir.join(format!("part-{i}.json"));
            let shard = format!("{i}/{count}");
            let mut args = vec!["enumerate", problem, "--shard", &shard];
            args.extend(extra);
            args.extend(["--json", part.to_str().unwrap()]);
            let out = wedged(&args);
            assert_code(&out, 0);
            assert!(text(&out.stdout).contains(&format!("shard {shard}: the search split")));
            part
        })
        .collect()
}

fn merge(parts: &[PathBuf], out: &Path) -> std::process::Output {
    let mut args = vec!["merge".to_string()];
    args.extend(parts.iter().map(|p| p.display().to_string()));
    args.extend(["--json".to_string(), out.display().to_string()]);
    wedged(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

/// Shards and merge against one run of `method`.
fn round_trip(problem: &str, method: &str, counts: &[usize]) {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.json");
    let out = wedged(&[
        "enumerate",
        problem,
        "--method",
        method,
        "--json",
        whole.to_str().unwrap(),
    ]);
    assert_code(&out, 0);
    let whole = json(&whole);
    assert!(whole.get("shard").is_none());
    assert!(!whole["patterns"].as_array().unwrap().is_empty());
    for &count in counts {
        let parts = shards(dir.path(), problem, count, &["--method", method]);
        let part = json(&parts[0]);
        assert_eq!(part["shard"]["count"], count);
        assert_eq!(part["shard"]["fingerprint"].as_str().unwrap().len(), 16);
        let merged = dir.path().join("merged.json");
        let out = merge(&parts, &merged);
        assert_code(&out, 0);
        assert!(text(&out.stdout).contains(&format!("merged {count} of {count} shards")));
        // The merge copies each piece's text from its part: the pieces' lines are the whole
        // run's, to the character.
        let piece_lines = |path: &Path| -> Vec<String> {
            std::fs::read_to_string(path)
                .unwrap()
                .lines()
                .filter(|l| l.trim_start().starts_with("{\"pattern\""))
                .map(|l| l.trim().trim_end_matches(',').to_string())
                .collect()
        };
        let lines = piece_lines(&merged);
        assert_eq!(lines.len(), whole["patterns"].as_array().unwrap().len());
        assert_eq!(lines, piece_lines(&dir.path().join("whole.json")));
        let merged = json(&merged);
        assert_eq!(
            answer(merged.clone()),
            answer(whole.clone()),
            "{problem} N = {count}"
        );
        // The same keys, in the same order.
        let keys = |v: &Value| v.as_object().unwrap().keys().cloned().collect::<Vec<_>>();
        assert_eq!(keys(&merged), keys(&whole));
        assert_eq!(keys(&merged["info"]), keys(&whole["info"]));
    }
}

#[test]
fn merged_shards_write_the_json_of_one_run() {
    round_trip(&example("plug2d.toml"), "pattern-search", &[3, 16]);
    round_trip(&example("plug2d.toml"), "bnb", &[2]);
    round_trip(&example("plug3d.toml"), "bnb", &[4]);
    round_trip(&example("cork2d.toml"), "bnb", &[3]);
    round_trip(&example("cork2d.toml"), "pattern-search", &[4]);
}

#[test]
fn a_lost_shard_is_named_and_the_merge_is_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let problem = example("plug2d.toml");
    let mut parts = shards(dir.path(), &problem, 4, &[]);
    parts.remove(2);
    let merged = dir.path().join("merged.json");
    let out = merge(&parts, &merged);
    assert_code(&out, 3);
    assert!(text(&out.stdout).contains("shard 3 of 4 missing"));
    let doc = json(&merged);
    assert_eq!(doc["complete"], false);
    assert_eq!(doc["outcome"], "incomplete");
    assert!(doc["stopped"]
        .as_str()
        .unwrap()
        .contains("shard 3 of 4 missing"));
}

#[test]
fn parts_that_do_not_belong_together_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let problem = example("plug2d.toml");
    let parts = shards(dir.path(), &problem, 2, &[]);
    let merged = dir.path().join("merged.json");
    // A shard given twice.
    let out = merge(&[parts[0].clone(), parts[0].clone()], &merged);
    assert_bad_input(&out, &["shard 1 of 2 given more than once"]);
    // A part of another run (another mu).
    let other = dir.path().join("other");
    std::fs::create_dir(&other).unwrap();
    let foreign = shards(&other, &problem, 2, &["--mu", "2.5"]);
    let out = merge(&[parts[0].clone(), foreign[1].clone()], &merged);
    assert_bad_input(&out, &["is a part of another run", "fingerprints"]);
    // A whole run's JSON, a file that is not there, a file that is not JSON.
    let whole = dir.path().join("whole.json");
    assert_code(
        &wedged(&["enumerate", &problem, "--json", whole.to_str().unwrap()]),
        0,
    );
    assert_bad_input(&merge(&[whole], &merged), &["not a part of a sharded run"]);
    let missing = dir.path().join("nothing.json");
    assert_bad_input(
        &merge(&[missing], &merged),
        &["nothing.json", "cannot read"],
    );
    let garbage = dir.path().join("garbage.json");
    std::fs::write(&garbage, "not json").unwrap();
    assert_bad_input(&merge(&[garbage], &merged), &["garbage.json", "not a JSON"]);
    assert!(!merged.exists(), "no merge is written from bad parts");
}

#[test]
fn shards_need_a_search_tree_and_a_part_file() {
    let problem = example("plug2d.toml");
    let out = wedged(&["enumerate", &problem, "--shard", "1/2"]);
    assert_bad_input(&out, &["--shard 1/2", "--json"]);
    let out = wedged(&[
        "enumerate",
        &problem,
        "--shard",
        "1/2",
        "--method",
        "pruned-dd",
        "--json",
        "-",
    ]);
    assert_bad_input(&out, &["pruned-dd has none to split"]);
    for bad in ["0/2", "3/2", "2", "x/y"] {
        let out = wedged(&["enumerate", &problem, "--shard", bad, "--json", "-"]);
        assert_code(&out, 2);
        assert!(text(&out.stderr).contains("--shard"), "{bad}");
    }
    let out = wedged(&[
        "enumerate",
        &problem,
        "--shard",
        "1/2",
        "--json",
        "-",
        "--svg",
        "pics",
    ]);
    assert_bad_input(&out, &["--svg draws the whole answer"]);
}

/// The Slurm example's scripts (examples/slurm), run as the shell loop `local.sh` with the
/// variables Slurm sets, write parts/ and all.json, the JSON of one run.
#[test]
fn the_slurm_scripts_give_one_run_answer() {
    let dir = tempfile::tempdir().unwrap();
    let problem = example("plug2d.toml");
    let script = example("slurm/local.sh");
    let out = std::process::Command::new("bash")
        .args([script.as_str(), problem.as_str(), "5"])
        .current_dir(dir.path())
        .env("WEDGED", env!("CARGO_BIN_EXE_wedged"))
        .output()
        .unwrap();
    assert_code(&out, 0);
    assert!(text(&out.stdout).contains("merged 5 of 5 shards"));
    assert!(dir.path().join("parts/part-5.json").exists());
    let whole = dir.path().join("whole.json");
    let out = wedged(&[
        "enumerate",
        &problem,
        "--method",
        "pattern-search",
        "--json",
        whole.to_str().unwrap(),
    ]);
    assert_code(&out, 0);
    assert_eq!(
        answer(json(&dir.path().join("all.json"))),
        answer(json(&whole))
    );
    // Without the array's variables the shard script says how to run it.
    let out = std::process::Command::new("bash")
        .args([example("slurm/shards.sbatch").as_str(), problem.as_str()])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_ne!(out.status.code(), Some(0));
    assert!(text(&out.stderr).contains("sbatch --array=1-N"));
}

/// `critical --shard I/N` and `merge`: the bracket of one run (each end within the tolerance),
/// the same keys; a part of `critical` does not merge with one of `enumerate`.
#[test]
fn critical_shards_merge_to_the_one_run_bracket() {
    let dir = tempfile::tempdir().unwrap();
    let problem = example("plug2d.toml");
    let whole_path = dir.path().join("whole.json");
    assert_code(
        &wedged(&["critical", &problem, "--json", whole_path.to_str().unwrap()]),
        0,
    );
    let whole = json(&whole_path);
    let count = 3;
    let mut wedged_parts = 0;
    let parts: Vec<PathBuf> = (1..=count)
        .map(|i| {
            let part = dir.path().join(format!("c-{i}.json"));
            let shard = format!("{i}/{count}");
            let out = wedged(&[
                "critical",
                &problem,
                "--shard",
                &shard,
                "--json",
                part.to_str().unwrap(),
            ]);
            assert_code(&out, 0);
            let stdout = text(&out.stdout);
            assert!(stdout.contains(&format!("shard {shard}: the search split")));
            // A part's lower end rules out its own contact sets only, and says so.
            if stdout.contains("mu* = ") {
                wedged_parts += 1;
                assert!(stdout.contains("this part: mu* = "), "{stdout}");
                assert!(
                    stdout.contains("no contact set of this part of the search wedges"),
                    "{stdout}"
                );
                assert!(
                    !stdout.contains("no friction coefficient wedges"),
                    "{stdout}"
                );
            }
            part
        })
        .collect();
    assert!(wedged_parts > 0, "no part found a wedge");
    let merged_path = dir.path().join("merged.json");
    let out = merge(&parts, &merged_path);
    assert_code(&out, 0);
    let merged = json(&merged_path);
    // The summary prints the bracket as `critical` does, to the digits it certifies, rounded
    // outwards: the ends printed still hold the JSON's.
    let line = text(&out.stdout);
    let printed = line
        .split("wedged, mu* = ")
        .nth(1)
        .and_then(|rest| rest.split(" (certified bracket [").nth(1))
        .and_then(|rest| rest.split("])").next())
        .unwrap_or_else(|| panic!("{line}"));
    let ends: Vec<f64> = printed.split(", ").map(|x| x.parse().unwrap()).collect();
    assert!(ends[0] <= merged["lower"].as_f64().unwrap(), "{line}");
    assert!(ends[1] >= merged["upper"].as_f64().unwrap(), "{line}");
    assert!(printed.len() < 30, "{line}");
    // Without a shard: incomplete, an upper end only, rounded up.
    let out = merge(&parts[..2], &merged_path);
    assert_code(&out, 3);
    let line = text(&out.stdout);
    let upper: f64 = line
        .split("incomplete, mu* <= ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .unwrap_or_else(|| panic!("{line}"))
        .parse()
        .unwrap();
    let partial = json(&merged_path);
    assert!(upper >= partial["upper"].as_f64().unwrap(), "{line}");
    assert_eq!(merged["status"], "wedged");
    let (mu, one) = (
        merged["mu_critical"].as_f64().unwrap(),
        whole["mu_critical"].as_f64().unwrap(),
    );
    assert!((mu - one).abs() <= 2e-9 * one, "{mu} against {one}");
    assert!(merged["lower"].as_f64().unwrap() <= one);
    assert!(whole["lower"].as_f64().unwrap() <= mu);
    let keys = |v: &Value| v.as_object().unwrap().keys().cloned().collect::<Vec<_>>();
    assert_eq!(keys(&merged), keys(&whole));
    assert_eq!(keys(&merged["info"]), keys(&whole["info"]));
    // A part of enumerate among them.
    let other = dir.path().join("other");
    std::fs::create_dir(&other).unwrap();
    let enumerate_parts = shards(&other, &problem, 3, &[]);
    let out = merge(
        &[parts[0].clone(), enumerate_parts[1].clone()],
        &merged_path,
    );
    assert_bad_input(&out, &["is a part of `wedged enumerate`"]);
    // Refusals.
    let out = wedged(&["critical", &problem, "--shard", "1/2"]);
    assert_bad_input(&out, &["--shard 1/2", "--json"]);
    let out = wedged(&[
        "critical", &problem, "--shard", "1/2", "--method", "faces", "--json", "-",
    ]);
    assert_bad_input(&out, &["faces has none to split"]);
}
