//! `combustion batch`'s manifest: a JSON file of render jobs, each a name, a scene and
//! any of `combustion render`'s options by their long names (parsed by the very
//! declaration `render` uses, so a job takes what `render` takes and is refused for what
//! `render` refuses), plus what the batch adds: outputs, criteria, the physics error.
//! docs/ci-rendering.md documents it; docs/batch-manifest.schema.json is its schema.
//!
//! Its arithmetic cannot overflow and it indexes nothing unchecked: clippy's
//! `arithmetic_side_effects` and `indexing_slicing` are denied here.
#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use clap::{CommandFactory, Parser};
use serde_json::{Map, Value};

use combustion::diff::{Criteria, Criterion};
use combustion::{escaped, shortened, Error, SceneSource};

use super::*;

/// The largest manifest read: 16 MiB.
pub(crate) const MAX_MANIFEST_BYTES: u64 = 16 << 20;

/// The most jobs a manifest holds.
pub const MAX_JOBS: usize = 100_000;

/// The longest job name, in bytes.
pub const MAX_NAME_BYTES: usize = 100;

/// Criteria of PNG outputs when the manifest and job give none: the same bytes.
pub(crate) const EXACT: &str = "max-channel-diff 0/255 on at most 0% of pixels";

/// Criteria of OpenEXR outputs when the manifest and job give none: the same values.
pub(crate) const EXACT_RADIANCE: &str = "max-relative-diff 0 on at most 0% of pixels";

/// The manifest's own keys.
const MANIFEST_KEYS: [&str; 5] = ["$schema", "jobs", "defaults", "criteria", "hdr_criteria"];

/// A job's keys beyond `render`'s options.
const JOB_KEYS: [&str; 6] = [
    "name",
    "scene",
    "outputs",
    "criteria",
    "hdr_criteria",
    "error",
];

/// `render` options a job cannot take: the batch names the outputs and the device, and
/// the scene is the job's `scene`.
const BATCH_OWNED: [&str; 6] = ["output", "hdr", "max-error", "device", "validate", "scene"];

/// A manifest, read and checked: every job parsed, every scene and environment file
/// found, names unique.
pub struct Manifest {
    /// The file's name without its folder and extension (JUnit's suite name).
    pub(crate) name: String,
    /// A digest of its text ([`text_digest`]): shards' results merge only with those of
    /// the same manifest, whatever its file is called.
    pub(crate) digest: String,
    /// The jobs, in the manifest's order (or the shard's share of them).
    pub(crate) jobs: Vec<Job>,
}

/// One render of the manifest.
pub(crate) struct Job {
    /// Its position in the manifest, from 0 (kept in a shard's results, for merging).
    pub(crate) index: usize,
    /// Its name: letters, digits, `-` and `_` (the outputs' file names).
    pub(crate) name: String,
    /// The scene and options, as `combustion render` takes them (paths resolved against
    /// the manifest's folder).
    pub(crate) render: RenderArgs,
    /// Whether the display image (PNG) is written.
    pub(crate) png: bool,
    /// Whether the radiance (OpenEXR) is written.
    pub(crate) exr: bool,
    /// What a PNG output must meet against its golden.
    pub(crate) criteria: Criteria,
    /// What an OpenEXR output must meet against its golden.
    pub(crate) hdr_criteria: Criteria,
    /// Whether the frame's error against the f64 reference is measured.
    pub(crate) error: bool,
}

/// `--shard I/N`: the I-th of N shares of the jobs (from 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// I, from 1.
    pub index: usize,
    /// N, at least 1.
    pub count: usize,
}

impl Shard {
    /// `I/N`, or a one-line error echoing the text shortened.
    pub fn parse(text: &str) -> Result<Shard, String> {
        let parsed = text
            .split_once('/')
            .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)));
        match parsed {
            Some((index, count)) if (1..=count).contains(&index) && count <= MAX_JOBS => {
                Ok(Shard { index, count })
            }
            _ => Err(format!(
                "`{}` is not I/N with 1 <= I <= N <= {MAX_JOBS}",
                shortened(text)
            )),
        }
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Manifest {
    /// Reads and checks the manifest at `path`; the error is one line naming the file
    /// and, where one is at fault, the job.
    pub(crate) fn read(path: &Path) -> Result<Manifest, Error> {
        let label = shortened(&path.display().to_string());
        let text = combustion::input::read_text(path, MAX_MANIFEST_BYTES, "a manifest")
            .map_err(|e| Error::Usage(format!("{label}: {e}")))?;
        let folder = path.parent().unwrap_or(Path::new(""));
        let name = path
            .file_stem()
            .map_or("manifest".into(), |s| s.to_string_lossy().into_owned());
        Self::parse(&text, folder, name).map_err(|e| Error::Usage(format!("{label}: {e}")))
    }

    /// The manifest `text`, its relative paths taken from `folder`.
    pub fn parse(text: &str, folder: &Path, name: String) -> Result<Manifest, String> {
        let value: Value =
            combustion::input::parse_json(text).map_err(|e| format!("not valid JSON: {e}"))?;
        let Value::Object(top) = value else {
            return Err("is not a JSON object with a `jobs` list".into());
        };
        if let Some(key) = top.keys().find(|k| !MANIFEST_KEYS.contains(&k.as_str())) {
            return Err(format!(
                "unknown key `{}` (a manifest has {})",
                shortened(key),
                MANIFEST_KEYS[1..].join(", ")
            ));
        }
        let defaults = match top.get("defaults") {
            None => Map::new(),
            Some(Value::Object(defaults)) => defaults.clone(),
            Some(_) => return Err("`defaults` is not an object".into()),
        };
        if defaults.contains_key("name") {
            return Err("`defaults` names no job (`name` is each job's own)".into());
        }
        let criteria = criteria_of(&top, "criteria", false)?.unwrap_or_else(exact);
        let hdr_criteria = criteria_of(&top, "hdr_criteria", true)?.unwrap_or_else(exact_radiance);
        let jobs = match top.get("jobs") {
            Some(Value::Array(jobs)) if jobs.is_empty() => return Err("`jobs` is empty".into()),
            Some(Value::Array(jobs)) if jobs.len() > MAX_JOBS => {
                return Err(format!("{} jobs: at most {MAX_JOBS}", jobs.len()))
            }
            Some(Value::Array(jobs)) => jobs,
            Some(_) => return Err("`jobs` is not a list".into()),
            None => return Err("there is no `jobs` list".into()),
        };
        let mut names = HashSet::new();
        let mut parsed = Vec::with_capacity(jobs.len());
        for (index, job) in jobs.iter().enumerate() {
            let Value::Object(job) = job else {
                return Err(format!("job {index} is not an object"));
            };
            let name = match job.get("name") {
                Some(Value::String(name)) => name.clone(),
                Some(_) => return Err(format!("job {index}: `name` is not a string")),
                None => return Err(format!("job {index} has no `name`")),
            };
            check_name(&name).map_err(|e| format!("job {index}: {e}"))?;
            // Names are file names, and some file systems ignore case.
            if !names.insert(name.to_lowercase()) {
                return Err(format!(
                    "job `{name}`: an earlier job has this name (names are file names, compared without case)"
                ));
            }
            let mut keys = defaults.clone();
            keys.extend(job.iter().map(|(k, v)| (k.clone(), v.clone())));
            keys.remove("name");
            let job = Job::parse(index, name.clone(), keys, folder, &criteria, &hdr_criteria)
                .map_err(|e| format!("job `{name}`: {e}"))?;
            parsed.push(job);
        }
        Ok(Manifest {
            name,
            digest: text_digest(text),
            jobs: parsed,
        })
    }

    /// Each job's position in the manifest and name, in the order kept.
    pub fn jobs(&self) -> impl Iterator<Item = (usize, &str)> {
        self.jobs.iter().map(|j| (j.index, j.name.as_str()))
    }

    /// A digest of its text ([`text_digest`]).
    pub fn digest(&self) -> &str {
        &self.digest
    }

    /// Keeps the jobs of `shard`: the jobs sorted by name are dealt out in turn, so
    /// every shard's share is the same whatever the manifest's order, and shares differ
    /// by one job at most.
    pub fn keep_shard(&mut self, shard: Shard) {
        let mut names: Vec<&str> = self.jobs.iter().map(|j| j.name.as_str()).collect();
        names.sort_unstable();
        let kept: HashSet<String> = names
            .iter()
            .enumerate()
            .filter(|(position, _)| position.checked_rem(shard.count) == shard.index.checked_sub(1))
            .map(|(_, name)| (*name).to_owned())
            .collect();
        self.jobs.retain(|job| kept.contains(&job.name));
    }
}

fn exact() -> Criteria {
    Criteria::parse(EXACT).expect("the exact criterion parses")
}

fn exact_radiance() -> Criteria {
    Criteria::parse(EXACT_RADIANCE).expect("the exact radiance criterion parses")
}

/// The criteria under `key`, if given: a string `Criteria::parse` takes, whose channel
/// terms are of the outputs they judge (8-bit for PNG, relative for OpenEXR).
fn criteria_of(
    keys: &Map<String, Value>,
    key: &str,
    radiance: bool,
) -> Result<Option<Criteria>, String> {
    let text = match keys.get(key) {
        None => return Ok(None),
        Some(Value::String(text)) => text,
        Some(_) => return Err(format!("`{key}` is not a string")),
    };
    let criteria = Criteria::parse(text).map_err(|e| format!("`{key}`: {e}"))?;
    let wrong =
        criteria.0.iter().flatten().find(
            |c| matches!(c, Criterion::ChannelDiff { relative, .. } if *relative != radiance),
        );
    if let Some(wrong) = wrong {
        return Err(format!(
            "`{key}`: `{wrong}` judges {} images; `{key}` judges {} ({})",
            if radiance { "PNG" } else { "OpenEXR" },
            if radiance { "OpenEXR" } else { "PNG" },
            if radiance {
                "use max-relative-diff"
            } else {
                "use max-channel-diff, or hdr_criteria for OpenEXR"
            }
        ));
    }
    Ok(Some(criteria))
}

/// The 64-bit FNV-1a hash of `text`, in hex: which manifest a shard ran (not a
/// security measure: it tells two manifests apart, it does not authenticate one).
pub fn text_digest(text: &str) -> String {
    let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{hash:016x}")
}

/// Checks a job name: 1 to [`MAX_NAME_BYTES`] letters, digits, `-` and `_` (no dots, so no
/// name's files are another's: NAME.png, NAME.exr, NAME.flip.png).
pub fn check_name(name: &str) -> Result<(), String> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || c == '-' || c == '_';
    if name.is_empty() || name.len() > MAX_NAME_BYTES || !name.chars().all(allowed) {
        return Err(format!(
            "the name `{}` is not 1 to {MAX_NAME_BYTES} letters, digits, `-` and `_` (it names the job's files)",
            shortened(name)
        ));
    }
    Ok(())
}

impl Job {
    fn parse(
        index: usize,
        name: String,
        mut keys: Map<String, Value>,
        folder: &Path,
        criteria: &Criteria,
        hdr_criteria: &Criteria,
    ) -> Result<Job, String> {
        let (png, exr) = match keys.remove("outputs") {
            None => (true, false),
            Some(Value::Array(kinds)) => {
                let mut kinds_seen = (false, false);
                for kind in &kinds {
                    match kind.as_str() {
                        Some("png") if !kinds_seen.0 => kinds_seen.0 = true,
                        Some("exr") if !kinds_seen.1 => kinds_seen.1 = true,
                        _ => {
                            return Err(
                                "`outputs` is not a list of \"png\" and \"exr\", each once".into()
                            )
                        }
                    }
                }
                if kinds.is_empty() {
                    return Err("`outputs` is empty".into());
                }
                kinds_seen
            }
            Some(_) => return Err("`outputs` is not a list".into()),
        };
        let job_criteria = criteria_of(&keys, "criteria", false)?;
        let job_hdr_criteria = criteria_of(&keys, "hdr_criteria", true)?;
        keys.remove("criteria");
        keys.remove("hdr_criteria");
        let error = match keys.remove("error") {
            None => false,
            Some(Value::Bool(error)) => error,
            Some(_) => return Err("`error` is not true or false".into()),
        };
        let scene = match keys.remove("scene") {
            Some(Value::String(scene)) => scene,
            Some(_) => return Err("`scene` is not a string".into()),
            None => return Err("there is no `scene` (builtin:NAME or a glTF file)".into()),
        };
        let scene = match SceneSource::parse(&scene) {
            SceneSource::File(path) => SceneSource::File(file_in(folder, &path, "scene")?),
            builtin => builtin,
        };
        let mut render = render_args(&keys)?;
        render.scene.scene = Some(scene);
        if let Some(EnvironmentChoice::File(path)) = &mut render.shading.environment {
            *path = file_in(folder, path, "environment")?;
        }
        Ok(Job {
            index,
            name,
            render,
            png,
            exr,
            criteria: job_criteria.unwrap_or_else(|| criteria.clone()),
            hdr_criteria: job_hdr_criteria.unwrap_or_else(|| hdr_criteria.clone()),
            error,
        })
    }
}

/// The longest path Linux resolves (`PATH_MAX`, its NUL included): a longer value names
/// no file, and is echoed shortened, not whole as paths are.
const MAX_PATH_BYTES: usize = 4096;

/// The `what` file `value` names from `folder`, which must be a file.
fn file_in(folder: &Path, value: &Path, what: &str) -> Result<PathBuf, String> {
    let path = folder.join(value);
    if path.as_os_str().len() >= MAX_PATH_BYTES {
        return Err(format!(
            "{what} file `{}` is longer than any path ({MAX_PATH_BYTES} bytes)",
            shortened(&value.to_string_lossy())
        ));
    }
    if !path.is_file() {
        return Err(format!(
            "{what} file {} is not found",
            escaped(&path.display().to_string())
        ));
    }
    Ok(path)
}

/// `render`'s options from a job's other keys, parsed by `render`'s own declaration:
/// `"width": 320` is `--width=320`, `"light-rig": true` is `--light-rig`, `"shadows":
/// true` is `--shadows=on`.
fn render_args(keys: &Map<String, Value>) -> Result<RenderArgs, String> {
    let command = Cli::command();
    let render = command
        .find_subcommand("render")
        .expect("the command line has render");
    let mut words = vec!["combustion".to_owned(), "render".to_owned()];
    for (key, value) in keys {
        let option = render
            .get_arguments()
            .find(|a| a.get_long() == Some(key.as_str()))
            .filter(|_| !BATCH_OWNED.contains(&key.as_str()));
        let Some(option) = option else {
            let kebab = key.replace('_', "-");
            let hint =
                if kebab != *key && render.get_arguments().any(|a| a.get_long() == Some(&kebab)) {
                    format!(" (did you mean `{kebab}`?)")
                } else {
                    String::new()
                };
            return Err(format!(
                "unknown key `{}`{hint}; a job has {} and `combustion render`'s options but {}",
                shortened(key),
                JOB_KEYS.join(", "),
                BATCH_OWNED.join(", ")
            ));
        };
        let switch = !option.get_action().takes_values();
        match (value, switch) {
            (Value::Bool(true), true) => words.push(format!("--{key}")),
            (Value::Bool(false), true) => {}
            (Value::Bool(on), false) => {
                words.push(format!("--{key}={}", if *on { "on" } else { "off" }))
            }
            (Value::Number(n), false) => words.push(format!("--{key}={n}")),
            (Value::String(text), false) => words.push(format!("--{key}={text}")),
            (_, true) => return Err(format!("`{key}` is a switch: true or false")),
            _ => return Err(format!("`{key}` takes a string, a number or true/false")),
        }
    }
    match Cli::try_parse_from(&words) {
        Ok(Cli {
            command: Command::Render(args),
        }) => Ok(args),
        Ok(_) => unreachable!("the words name render"),
        Err(e) => {
            let message = value_shortened(e).render().to_string();
            let first = message.lines().next().unwrap_or_default();
            Err(first.trim_start_matches("error: ").to_owned())
        }
    }
}

#[cfg(test)]
#[allow(clippy::indexing_slicing)] // a test fails by a panic
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Manifest, String> {
        Manifest::parse(text, Path::new(""), "m".into())
    }

    fn error(text: &str) -> String {
        match parse(text) {
            Ok(_) => panic!("{text} is accepted"),
            Err(e) => e,
        }
    }

    #[test]
    fn a_job_takes_render_options_by_their_long_names() {
        let m = parse(
            r#"{"criteria": "mean-flip <= 0.01",
                "defaults": {"width": 320, "height": 180, "scene": "builtin:spheres"},
                "jobs": [
                  {"name": "a"},
                  {"name": "b", "scene": "builtin:grid-7x7", "width": 64, "light-rig": true,
                   "shadows": true, "fresnel": "schlick", "camera": "orbit:30,20",
                   "ev": -1, "outputs": ["exr", "png"], "error": true,
                   "hdr_criteria": "max-relative-diff 1e-3 on at most 1% of pixels"}
                ]}"#,
        )
        .unwrap();
        let [a, b] = &m.jobs[..] else { panic!() };
        assert_eq!(
            (a.index, a.name.as_str(), a.render.frame.width),
            (0, "a", 320)
        );
        assert_eq!(
            a.render.scene.source(),
            SceneSource::Builtin("spheres".into())
        );
        assert!(a.png && !a.exr && !a.error);
        assert_eq!(a.criteria, Criteria::parse("mean-flip <= 0.01").unwrap());
        assert_eq!(a.hdr_criteria, exact_radiance());
        assert_eq!((b.render.frame.width, b.render.frame.height), (64, 180));
        assert_eq!(
            b.render.scene.source(),
            SceneSource::Builtin("grid-7x7".into())
        );
        assert!(b.render.shading.light_rig && b.render.shading.shadows && b.png && b.exr);
        assert_eq!(b.render.frame.ev, Some(-1.0));
        assert_eq!(
            b.render.frame.fresnel,
            combustion::renderer::FresnelModel::Schlick
        );
        assert_eq!(
            b.render.camera.camera,
            CameraChoice::Orbit {
                azimuth: 30.0,
                elevation: 20.0,
                distance: 1.0
            }
        );
        assert!(b.error);
    }

    /// Each mistake is one line naming the job and what is wrong.
    #[test]
    fn bad_manifests_are_refused_naming_the_job() {
        let cases = [
            ("[]", "is not a JSON object"),
            ("{\"jobs\": []}", "`jobs` is empty"),
            ("{\"job\": []}", "unknown key `job`"),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres"}], "jobs": [{"name": "b", "scene": "builtin:spheres"}]}"#,
                "the key `jobs` appears twice in one object",
            ),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "width": 8, "width": 16}]}"#,
                "the key `width` appears twice in one object",
            ),
            ("{\"jobs\": [{\"scene\": \"builtin:spheres\"}]}", "job 0 has no `name`"),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres"}, {"name": "A", "scene": "builtin:spheres"}]}"#,
                "job `A`: an earlier job has this name",
            ),
            (r#"{"jobs": [{"name": "a.b", "scene": "builtin:spheres"}]}"#, "job 0: the name `a.b`"),
            (r#"{"jobs": [{"name": "a"}]}"#, "job `a`: there is no `scene`"),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "widht": 3}]}"#,
                "job `a`: unknown key `widht`",
            ),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "tone_mapping": "agx"}]}"#,
                "did you mean `tone-mapping`?",
            ),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "output": "x.png"}]}"#,
                "job `a`: unknown key `output`",
            ),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "width": 0}]}"#,
                "job `a`: invalid value '0' for '--width <N>'",
            ),
            (
                r#"{"jobs": [{"name": "a", "scene": "missing.glb"}]}"#,
                "job `a`: scene file missing.glb is not found",
            ),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "environment": "sky.hdr"}]}"#,
                "job `a`: environment file sky.hdr is not found",
            ),
            (
                r#"{"criteria": "max-relative-diff 1e-3 on at most 1% of pixels", "jobs": [{"name": "a", "scene": "builtin:spheres"}]}"#,
                "`criteria`: `max-relative-diff 0.001 on at most 1% of pixels` judges OpenEXR images",
            ),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "outputs": ["png", "png"]}]}"#,
                "job `a`: `outputs` is not a list",
            ),
            (
                r#"{"jobs": [{"name": "a", "scene": "builtin:spheres", "light-rig": 1}]}"#,
                "job `a`: `light-rig` is a switch",
            ),
        ];
        for (text, expected) in cases {
            let e = error(text);
            assert!(e.contains(expected), "{text}: {e}");
            assert!(!e.contains('\n'), "{text}: {e}");
        }
    }

    /// The schema (docs/batch-manifest.schema.json) names only keys a job has, and its
    /// enumerations are the values `render` takes: it cannot drift from the declaration.
    #[test]
    fn the_schema_agrees_with_the_command_line() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/docs/batch-manifest.schema.json"
        );
        let schema: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let top: Vec<&str> = schema["properties"]
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        let mut expected = MANIFEST_KEYS.to_vec();
        expected.sort_unstable();
        assert_eq!(top, expected);
        let command = Cli::command();
        let render = command.find_subcommand("render").unwrap();
        let properties = schema["$defs"]["options"]["properties"]
            .as_object()
            .unwrap();
        for key in JOB_KEYS {
            assert!(properties.contains_key(key), "{key}");
        }
        for (key, property) in properties {
            if JOB_KEYS.contains(&key.as_str()) {
                continue;
            }
            let option = render
                .get_arguments()
                .find(|a| a.get_long() == Some(key.as_str()))
                .unwrap_or_else(|| panic!("the schema's `{key}` is no option of render"));
            assert!(!BATCH_OWNED.contains(&key.as_str()), "{key}");
            if let Some(values) = property["enum"].as_array() {
                let mut listed: Vec<String> = values
                    .iter()
                    .filter_map(|v| v.as_str().map(str::to_owned))
                    .collect();
                let mut possible: Vec<String> = option
                    .get_possible_values()
                    .iter()
                    .map(|v| v.get_name().to_owned())
                    .collect();
                listed.sort();
                possible.sort();
                assert_eq!(listed, possible, "{key}");
            }
        }
    }

    /// Shards deal the jobs sorted by name: together they are the manifest, each job
    /// once; their sizes differ by one at most; the manifest's order does not change them.
    #[test]
    fn shards_partition_the_jobs_by_name() {
        let names = ["k", "b", "x", "a", "q", "c", "m"];
        let manifest = |names: &[&str]| {
            let jobs: Vec<String> = names
                .iter()
                .map(|n| format!(r#"{{"name": "{n}", "scene": "builtin:spheres"}}"#))
                .collect();
            parse(&format!("{{\"jobs\": [{}]}}", jobs.join(","))).unwrap()
        };
        let shares = |names: &[&str]| -> Vec<Vec<String>> {
            (1..=3)
                .map(|index| {
                    let mut m = manifest(names);
                    m.keep_shard(Shard { index, count: 3 });
                    let mut share: Vec<String> = m.jobs.into_iter().map(|j| j.name).collect();
                    share.sort();
                    share
                })
                .collect()
        };
        let split = shares(&names);
        assert_eq!(split, [vec!["a", "k", "x"], vec!["b", "m"], vec!["c", "q"]]);
        let mut reversed = names;
        reversed.reverse();
        assert_eq!(shares(&reversed), split);
        assert_eq!(Shard::parse("2/3"), Ok(Shard { index: 2, count: 3 }));
        for bad in ["0/3", "4/3", "1", "a/b", "1/0"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }
}
