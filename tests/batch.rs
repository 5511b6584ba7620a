//! `combustion batch`: a manifest of jobs rendered in one process, compared with goldens
//! by stated criteria, reported as JSON and JUnit XML; shards of a CI matrix merged back
//! into the one run's result; bad manifests refused in one line naming the job.

use crate::common;

use std::path::Path;

use serde_json::Value;

use common::combustion;

fn scratch(name: &str) -> common::Scratch {
    common::Scratch::new("batch", name)
}

fn text(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn results(folder: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(folder.join("results.json")).unwrap()).unwrap()
}

/// `combustion batch --merge SHARDS… -o MERGED`, which must succeed.
/// Runs `batch MANIFEST --shard i/count` for i = 1..=count, each into `dir`/shard-i:
/// each shard's folder and its exit code, standard output and error.
fn run_shards(
    manifest: &Path,
    dir: &Path,
    count: u32,
) -> Vec<(std::path::PathBuf, (i32, String, String))> {
    (1..=count)
        .map(|i| {
            let folder = dir.join(format!("shard-{i}"));
            let shard = format!("{i}/{count}");
            let run = combustion(&[
                "batch",
                text(manifest),
                "-o",
                text(&folder),
                "--shard",
                &shard,
            ]);
            (folder, run)
        })
        .collect()
}

fn merge_shards(shards: &[std::path::PathBuf], merged: &Path) {
    let mut args = vec!["batch", "--merge"];
    args.extend(shards.iter().map(|s| text(s)));
    args.extend(["-o", text(merged)]);
    let (code, stdout, stderr) = combustion(&args);
    assert_eq!(code, 0, "{stdout}{stderr}");
}

/// `combustion batch MANIFEST -o OUT --goldens GOLDENS EXTRA…`.
fn batch(manifest: &str, out: &Path, goldens: &Path, extra: &[&str]) -> (i32, String, String) {
    let mut args = vec![
        "batch",
        manifest,
        "-o",
        text(out),
        "--goldens",
        text(goldens),
    ];
    args.extend(extra);
    combustion(&args)
}

/// Each job's name → its status, comparisons and physics error (no timings, no paths).
fn outcomes(run: &Value) -> Vec<(String, String, Vec<Value>, Value)> {
    run["jobs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| {
            let comparisons = j["outputs"]
                .as_array()
                .unwrap()
                .iter()
                .map(|o| o["comparison"].clone())
                .collect();
            (
                j["name"].as_str().unwrap().to_owned(),
                j["status"].as_str().unwrap().to_owned(),
                comparisons,
                j["physics_error"].clone(),
            )
        })
        .collect()
}

/// The manifest of the batch tests: built-in scenes seen from their own cameras, an
/// orbit and a framing view, with shadows, another Fresnel term, both outputs, the
/// physics error; and sample models from `../shared` when it is there (one animated).
fn manifest(dir: &Path) -> String {
    let mut jobs = vec![
        r#"{"name": "spheres", "scene": "builtin:spheres", "outputs": ["png", "exr"], "error": true}"#.to_owned(),
        r#"{"name": "spheres-schlick", "scene": "builtin:spheres", "fresnel": "schlick", "error": true}"#.to_owned(),
        r#"{"name": "spheres-orbit", "scene": "builtin:spheres", "camera": "orbit:40,25", "shadows": true}"#.to_owned(),
        r#"{"name": "grid-framing", "scene": "builtin:grid-7x7", "camera": "framing", "light-rig": true}"#.to_owned(),
        r#"{"name": "grid", "scene": "builtin:grid-7x7", "ev": 0.5}"#.to_owned(),
    ];
    if let Some(samples) = common::shared_gltf_samples() {
        let model = |name: &str| {
            samples
                .join(name)
                .join("glTF-Binary")
                .join(format!("{name}.glb"))
                .to_str()
                .unwrap()
                .replace('\\', "/")
        };
        jobs.push(format!(
            r#"{{"name": "metal-rough", "scene": "{}", "camera": "orbit:-30,10,1.2"}}"#,
            model("MetalRoughSpheresNoTextures")
        ));
        jobs.push(format!(
            r#"{{"name": "cesium-man", "scene": "{}", "time": 1.0}}"#,
            model("CesiumMan")
        ));
    }
    let text = format!(
        r#"{{"criteria": "max-channel-diff 2/255 on at most 0.1% of pixels and mean-flip <= 0.005",
            "defaults": {{"width": 96, "height": 64}},
            "jobs": [{}]}}"#,
        jobs.join(",\n")
    );
    let path = dir.join("manifest.json");
    std::fs::write(&path, &text).unwrap();
    path.to_str().unwrap().to_owned()
}

/// Goldens written once, then the same manifest passes against them, in one process:
/// every job's outputs byte-equal to its goldens (the figures say 0 difference), the
/// JUnit file counts the jobs with no failure, the table lists them all; nothing is
/// written beside the manifest. A golden changed to a brighter render fails its job
/// alone (exit 1, the criterion named, a FLIP heat map written) while the others pass.
/// The physics error is the frame's against the f64 reference of the scene: small for
/// the full Fresnel equations, larger with Schlick's approximation.
#[test]
fn a_manifest_renders_compares_with_goldens_and_reports_junit() {
    let dir = scratch("goldens");
    let manifest = manifest(&dir);
    let (goldens, first, second) = (dir.join("goldens"), dir.join("first"), dir.join("second"));
    let (code, stdout, stderr) = batch(
        &manifest,
        &first,
        &goldens,
        &["--update-goldens", "--validate"],
    );
    assert_eq!(code, 0, "{stdout}{stderr}");
    let jobs = results(&first)["jobs"].as_array().unwrap().len();
    assert!(jobs >= 5);
    assert!(
        stdout.contains(&format!("{jobs} goldens written")),
        "{stdout}"
    );
    assert_eq!(common::listing(&dir), ["first", "goldens", "manifest.json"]);

    let (code, stdout, stderr) = batch(&manifest, &second, &goldens, &["--validate"]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let run = results(&second);
    for (name, status, comparisons, _) in outcomes(&run) {
        assert_eq!(status, "passed", "{name}");
        for c in comparisons {
            assert_eq!(c["max_channel_diff"], 0.0, "{name}: {c}");
            assert_eq!(c["flip_mean"], 0.0, "{name}: {c}");
        }
        assert!(stdout.contains(&name), "{stdout}");
    }
    let junit = std::fs::read_to_string(second.join("junit.xml")).unwrap();
    assert!(
        junit.contains(&format!("tests=\"{jobs}\" failures=\"0\" errors=\"0\"")),
        "{junit}"
    );
    assert_eq!(junit.matches("<testcase ").count(), jobs);
    let mut expected = vec![
        "junit.xml".to_owned(),
        "results.json".to_owned(),
        "spheres.exr".to_owned(),
    ];
    expected.extend(
        run["jobs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| format!("{}.png", j["name"].as_str().unwrap())),
    );
    expected.sort();
    assert_eq!(common::listing(&second), expected);

    // The physics error, end to end: the full equations within the renderer's bounds
    // (tests/end_to_end.rs), Schlick's approximation well beyond them.
    let physics = |name: &str| {
        let job = run["jobs"]
            .as_array()
            .unwrap()
            .iter()
            .find(|j| j["name"] == name)
            .unwrap();
        let p = &job["physics_error"];
        assert_eq!(p["wrong_surface_pixels"], 0, "{name}: {p}");
        assert!(p["compared_pixels"].as_u64().unwrap() > 300, "{name}: {p}");
        (
            p["mean_relative"].as_f64().unwrap(),
            p["flip_mean"].as_f64().unwrap(),
        )
    };
    let (full, full_flip) = physics("spheres");
    let (schlick, schlick_flip) = physics("spheres-schlick");
    assert!(full < 1e-3, "{full}");
    assert!(
        schlick > 10.0 * full,
        "Schlick {schlick} against full {full}"
    );
    assert!(schlick_flip > full_flip, "{schlick_flip} {full_flip}");

    // One golden brighter: that job fails by its criterion, the others pass.
    let brighter = dir.join("brighter");
    std::fs::create_dir_all(&brighter).unwrap();
    let (code, _, stderr) = combustion(&[
        "render",
        "builtin:grid-7x7",
        "--width",
        "96",
        "--height",
        "64",
        "--ev",
        "0.7",
        "-o",
        text(&brighter.join("grid.png")),
    ]);
    assert_eq!(code, 0, "{stderr}");
    std::fs::copy(brighter.join("grid.png"), goldens.join("grid.png")).unwrap();
    let third = dir.join("third");
    let (code, stdout, stderr) = batch(&manifest, &third, &goldens, &[]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    let errors: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("error: "))
        .collect();
    assert_eq!(
        errors,
        ["error: 1 of 7 jobs did not pass: grid"].map(|e| e.replace('7', &jobs.to_string()))
    );
    let run = results(&third);
    for (name, status, _, _) in outcomes(&run) {
        assert_eq!(
            status,
            if name == "grid" { "failed" } else { "passed" },
            "{name}"
        );
    }
    let grid = &run["jobs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|j| j["name"] == "grid")
        .unwrap();
    let message = grid["message"].as_str().unwrap();
    assert!(
        message.starts_with("grid.png: max-channel-diff 2/255 on at most 0.1% of pixels:"),
        "{message}"
    );
    assert_eq!(grid["outputs"][0]["heat_map"], "grid.flip.png");
    assert!(third.join("grid.flip.png").is_file());
    let junit = std::fs::read_to_string(third.join("junit.xml")).unwrap();
    assert!(junit.contains("failures=\"1\" errors=\"0\""), "{junit}");
    assert!(
        junit.contains("<failure message=\"grid.png: max-channel-diff"),
        "{junit}"
    );
}

/// Three shards of the manifest, rendered apart as a CI matrix would, merge into the
/// one run's result: the same jobs, statuses, comparisons and physics errors; each job
/// rendered by one shard; a merge missing a shard, or given one twice, is refused.
#[test]
fn shards_merge_to_the_one_runs_result() {
    let dir = scratch("shards");
    let manifest = manifest(&dir);
    let goldens = dir.join("goldens");
    let (code, _, stderr) = batch(
        &manifest,
        &dir.join("whole"),
        &goldens,
        &["--update-goldens"],
    );
    assert_eq!(code, 0, "{stderr}");
    let whole_dir = dir.join("again");
    let (code, _, stderr) = batch(&manifest, &whole_dir, &goldens, &[]);
    assert_eq!(code, 0, "{stderr}");
    let whole = outcomes(&results(&whole_dir));
    let mut shards = Vec::new();
    for i in 1..=3 {
        let folder = dir.join(format!("shard-{i}"));
        let (code, _, stderr) = batch(
            &manifest,
            &folder,
            &goldens,
            &["--shard", &format!("{i}/3")],
        );
        assert_eq!(code, 0, "{stderr}");
        assert!(!results(&folder)["jobs"].as_array().unwrap().is_empty());
        shards.push(folder);
    }
    let merged = dir.join("merged");
    merge_shards(&shards, &merged);
    assert_eq!(outcomes(&results(&merged)), whole);
    let junit = std::fs::read_to_string(merged.join("junit.xml")).unwrap();
    assert_eq!(junit.matches("<testcase ").count(), whole.len());

    let (first, second) = (text(&shards[0]), text(&shards[1]));
    for (folders, expected) in [
        ([first, second], "shard 3/3 is missing"),
        ([first, first], "is given twice"),
    ] {
        let out = dir.join("refused");
        let (code, _, stderr) =
            combustion(&["batch", "--merge", folders[0], folders[1], "-o", text(&out)]);
        assert_eq!(code, 1);
        assert!(stderr.contains(expected), "{stderr}");
    }
}

/// More shards than jobs: a shard that holds no job renders nothing, says so, exits 0
/// with results that list no job, and the shards still merge to every job (it panicked,
/// index out of bounds, and left an empty folder that `--merge` refused).
#[test]
fn a_shard_without_jobs_has_empty_results_and_merges() {
    let dir = scratch("empty-shard");
    let manifest = dir.join("two.json");
    std::fs::write(
        &manifest,
        r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "width": 32, "height": 24},
                      {"name": "b", "scene": "builtin:spheres", "width": 32, "height": 24}]}"#,
    )
    .unwrap();
    let mut shards = Vec::new();
    for (i, (folder, (code, stdout, stderr))) in (1..).zip(run_shards(&manifest, &dir, 3)) {
        assert_eq!(code, 0, "{stdout}{stderr}");
        let jobs = results(&folder)["jobs"].as_array().unwrap().len();
        assert_eq!(jobs, usize::from(i < 3), "shard {i}/3");
        if i == 3 {
            assert!(stderr.contains("--shard 3/3: no job of"), "{stderr}");
            assert!(!stderr.contains("panicked"), "{stderr}");
        }
        shards.push(folder);
    }
    let merged = dir.join("merged");
    merge_shards(&shards, &merged);
    assert_eq!(results(&merged)["jobs"].as_array().unwrap().len(), 2);
}

/// A shard's results file is read text: a message holding an escape sequence or a line
/// break is shown by `--merge` on one line with the control characters escaped, in the
/// table and in the merged results (it reached the terminal raw).
#[test]
fn merged_messages_reach_no_terminal_raw() {
    let dir = scratch("merged-escapes");
    let manifest = dir.join("two.json");
    std::fs::write(dir.join("broken.gltf"), "{}").unwrap();
    std::fs::write(
        &manifest,
        r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "width": 32, "height": 24},
                      {"name": "b", "scene": "broken.gltf", "width": 32, "height": 24}]}"#,
    )
    .unwrap();
    let shards: Vec<_> = run_shards(&manifest, &dir, 2)
        .into_iter()
        .map(|(folder, _)| folder)
        .collect();
    // Job b failed to load: its message, rewritten as a hostile file would hold it.
    let file = shards[1].join("results.json");
    let mut written = results(&shards[1]);
    written["jobs"][0]["message"] = "clear\u{1b}[2J\nsecond line".into();
    std::fs::write(&file, serde_json::to_vec(&written).unwrap()).unwrap();
    let merged = dir.join("merged");
    let (code, stdout, stderr) = combustion(&[
        "batch",
        "--merge",
        text(&shards[0]),
        text(&shards[1]),
        "-o",
        text(&merged),
    ]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    assert!(!stdout.contains('\u{1b}'), "{stdout:?}");
    assert!(stdout.contains("clear\\u{1b}[2J; second line"), "{stdout}");
    let message = results(&merged)["jobs"][1]["message"].clone();
    assert_eq!(message, "clear\\u{1b}[2J; second line");
}

/// What a batch cannot do is said in one line before anything renders (a manifest's
/// mistakes name the job; exit 2), or per job while the others go on: a scene that
/// fails to load, a golden of another size.
#[test]
fn bad_batches_are_refused_in_one_line() {
    let dir = scratch("bad");
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_owned()
    };
    let out = dir.join("out");
    let refused = |manifest: &str, extra: &[&str], expected: &str| {
        let mut args = vec!["batch", manifest, "-o", text(&out)];
        args.extend(extra);
        let (code, _, stderr) = combustion(&args);
        assert_eq!(code, 2, "{stderr}");
        let errors: Vec<&str> = stderr
            .lines()
            .filter(|l| l.starts_with("error: "))
            .collect();
        assert_eq!(errors.len(), 1, "{stderr}");
        assert!(errors[0].contains(expected), "{stderr}");
    };
    refused(
        &write(
            "dup.json",
            r#"{"jobs": [{"name": "a", "scene": "builtin:spheres"}, {"name": "a", "scene": "builtin:spheres"}]}"#,
        ),
        &[],
        "job `a`: an earlier job has this name",
    );
    refused(
        &write(
            "key.json",
            r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "frames": 3}]}"#,
        ),
        &[],
        "job `a`: unknown key `frames`",
    );
    refused(
        &write(
            "file.json",
            r#"{"jobs": [{"name": "a", "scene": "nowhere.glb"}]}"#,
        ),
        &[],
        "job `a`: scene file",
    );
    refused(&write("json.json", "{\"jobs\": ["), &[], "not valid JSON");
    let good = write(
        "good.json",
        r#"{"defaults": {"width": 32, "height": 24}, "jobs": [
        {"name": "a", "scene": "builtin:spheres"},
        {"name": "b", "scene": "builtin:spheres", "width": 40, "camera": "0"},
        {"name": "c", "scene": "builtin:grid-7x7", "width": 40}]}"#,
    );
    refused(
        &good,
        &["--goldens", text(&dir.join("none"))],
        "no such folder",
    );
    // An output folder that is a file.
    let file = write("a-file", "");
    let (code, _, stderr) = combustion(&["batch", &good, "-o", &file]);
    assert_ne!(code, 0);
    assert_eq!(
        stderr.lines().filter(|l| l.starts_with("error: ")).count(),
        1,
        "{stderr}"
    );
    assert!(!out.exists(), "nothing written by refused batches");

    // Per job: b's camera index names no camera of a built-in scene; c's golden is of
    // another size (a's, 32x24). a passes.
    let goldens = dir.join("goldens");
    let (code, _, stderr) = batch(&good, &out, &goldens, &["--update-goldens"]);
    assert_eq!(code, 1, "{stderr}");
    std::fs::copy(goldens.join("a.png"), goldens.join("c.png")).unwrap();
    let (code, stdout, stderr) = batch(&good, &out, &goldens, &[]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    let run = results(&out);
    let job = |name: &str| {
        run["jobs"]
            .as_array()
            .unwrap()
            .iter()
            .find(|j| j["name"] == name)
            .unwrap()
            .clone()
    };
    assert_eq!(job("a")["status"], "passed");
    assert_eq!(job("b")["status"], "error");
    assert!(
        job("b")["message"]
            .as_str()
            .unwrap()
            .contains("--camera 0: builtin:spheres has one camera"),
        "{}",
        job("b")
    );
    assert_eq!(job("c")["status"], "failed");
    assert!(
        job("c")["message"]
            .as_str()
            .unwrap()
            .contains("c.png against its golden"),
        "{}",
        job("c")
    );
    assert!(
        stderr.contains("2 of 3 jobs did not pass: b, c"),
        "{stderr}"
    );
}

/// A job path traces with a sample count (`"samples"`), the image `render --samples`
/// makes of the same scene, byte for byte; `"accumulate-until"` renders too; and
/// `"error": true` beside either is refused for that job in one line, the others going on.
#[test]
fn a_job_path_traces_with_a_sample_count() {
    let dir = scratch("samples");
    let manifest = dir.join("traced.json");
    std::fs::write(
        &manifest,
        r#"{"jobs": [
            {"name": "box", "scene": "builtin:cornell-box", "width": 16, "height": 12,
             "path-trace": "on", "samples": 8, "outputs": ["exr"]},
            {"name": "box-until", "scene": "builtin:cornell-box", "width": 16, "height": 12,
             "path-trace": "on", "accumulate-until": 0.5},
            {"name": "box-error", "scene": "builtin:cornell-box", "width": 16, "height": 12,
             "path-trace": "on", "samples": 8, "error": true}]}"#,
    )
    .unwrap();
    let out = dir.join("out");
    let (code, stdout, stderr) = combustion(&["batch", text(&manifest), "-o", text(&out)]);
    assert_eq!(code, 1, "one job fails: {stdout}{stderr}");
    let run = results(&out);
    let jobs = run["jobs"].as_array().unwrap();
    let status = |name: &str| {
        jobs.iter()
            .find(|j| j["name"] == name)
            .map(|j| {
                (
                    j["status"].as_str().unwrap().to_owned(),
                    j["message"].clone(),
                )
            })
            .unwrap()
    };
    assert_eq!(status("box").0, "rendered");
    assert_eq!(status("box-until").0, "rendered");
    let (failed, message) = status("box-error");
    assert_eq!(failed, "error");
    assert!(
        message
            .as_str()
            .unwrap()
            .contains("cannot be combined with samples or accumulate-until"),
        "{message}"
    );
    let alone = dir.join("alone.exr");
    let (code, _, stderr) = combustion(&[
        "render",
        "builtin:cornell-box",
        "--path-trace",
        "on",
        "--samples",
        "8",
        "--width",
        "16",
        "--height",
        "12",
        "--hdr",
        text(&alone),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let written = std::fs::read_dir(&out)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("box."))
                && p.extension().is_some_and(|e| e == "exr")
        })
        .expect("the job's EXR");
    assert_eq!(
        std::fs::read(written).unwrap(),
        std::fs::read(&alone).unwrap()
    );
}

/// `--merge` takes only shards of one manifest's one split: shards of two manifests that
/// share a file name, a results file claiming shard 0/0, and a job whose name the
/// manifest rule refuses (it names files) are refused in one line naming the shard's
/// results (each was merged).
#[test]
fn merge_refuses_what_no_split_of_one_manifest_makes() {
    let dir = scratch("merge-refusals");
    let job = |name: &str| {
        format!(r#"{{"name": "{name}", "scene": "builtin:spheres", "width": 8, "height": 8}}"#)
    };
    let shard = |folder: &Path, manifest: &Path, which: &str| {
        let (code, stdout, stderr) = combustion(&[
            "batch",
            text(manifest),
            "-o",
            text(folder),
            "--shard",
            which,
        ]);
        assert_eq!(code, 0, "{stdout}{stderr}");
    };
    // Two manifests, both named jobs.json, of other jobs.
    for (sub, jobs) in [("one", [job("a"), job("b")]), ("two", [job("c"), job("d")])] {
        std::fs::create_dir_all(dir.join(sub)).unwrap();
        std::fs::write(
            dir.join(sub).join("jobs.json"),
            format!(r#"{{"jobs": [{}, {}]}}"#, jobs[0], jobs[1]),
        )
        .unwrap();
    }
    let (first, second) = (dir.join("first"), dir.join("second"));
    shard(&first, &dir.join("one").join("jobs.json"), "1/2");
    shard(&second, &dir.join("two").join("jobs.json"), "2/2");
    let merged = dir.join("merged");
    let merge = |shards: &[&Path]| {
        let mut args = vec!["batch", "--merge"];
        args.extend(shards.iter().map(|s| text(s)));
        args.extend(["-o", text(&merged)]);
        combustion(&args)
    };
    let (code, _, stderr) = merge(&[&first, &second]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("the results of another manifest named `jobs`"),
        "{stderr}"
    );
    // A results file claiming shard 0/0.
    let own_second = dir.join("own-second");
    shard(&own_second, &dir.join("one").join("jobs.json"), "2/2");
    let results_file = own_second.join("results.json");
    let honest = std::fs::read_to_string(&results_file).unwrap();
    let mut run: Value = serde_json::from_str(&honest).unwrap();
    run["shard"] = serde_json::json!({"index": 0, "count": 0});
    std::fs::write(&results_file, run.to_string()).unwrap();
    let (code, _, stderr) = merge(&[&first, &own_second]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("shard 0/0 is no shard"), "{stderr}");
    // A job's name that names files outside the folder.
    let mut run: Value = serde_json::from_str(&honest).unwrap();
    run["jobs"][0]["name"] = "../evil".into();
    std::fs::write(&results_file, run.to_string()).unwrap();
    let (code, _, stderr) = merge(&[&first, &own_second]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("a job's result: the name `../evil`"),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    // Honest, the two shards of one manifest merge.
    std::fs::write(&results_file, honest).unwrap();
    let (code, _, stderr) = merge(&[&first, &own_second]);
    assert_eq!(code, 0, "{stderr}");
}

/// A run into a folder an earlier run wrote leaves none of the earlier run's images
/// beside its own results (they stayed, as if this run had written them), and nothing
/// else of the folder is touched; a junit.xml that cannot be written is said before any
/// job renders (it was said once every job had rendered).
#[test]
fn a_run_replaces_the_earlier_runs_outputs_and_checks_its_reports_first() {
    let dir = scratch("rerun");
    let out = dir.join("out");
    let manifest = |jobs: &[&str]| {
        let path = dir.join("jobs.json");
        let jobs: Vec<String> = jobs
            .iter()
            .map(|name| {
                format!(
                    r#"{{"name": "{name}", "scene": "builtin:spheres", "width": 8, "height": 8}}"#
                )
            })
            .collect();
        std::fs::write(&path, format!(r#"{{"jobs": [{}]}}"#, jobs.join(", "))).unwrap();
        path
    };
    let first = manifest(&["old", "kept"]);
    let (code, stdout, stderr) = combustion(&["batch", text(&first), "-o", text(&out)]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(out.join("old.png").exists() && out.join("kept.png").exists());
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let second = manifest(&["kept"]);
    let (code, stdout, stderr) = combustion(&["batch", text(&second), "-o", text(&out)]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(
        !out.join("old.png").exists(),
        "the earlier run's image is gone"
    );
    assert!(out.join("kept.png").exists());
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    // junit.xml a folder: refused before any job renders.
    let blocked = dir.join("blocked");
    std::fs::create_dir_all(blocked.join("junit.xml")).unwrap();
    let (code, _, stderr) = combustion(&["batch", text(&second), "-o", text(&blocked)]);
    assert_ne!(code, 0, "{stderr}");
    assert!(stderr.contains("junit.xml: it names a folder"), "{stderr}");
    assert!(!blocked.join("kept.png").exists(), "no job rendered");
}
