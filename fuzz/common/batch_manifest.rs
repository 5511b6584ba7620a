//! What the `batch_manifest` fuzz target does with one input (shared with the test that
//! replays its corpus, tests/fuzz_corpus.rs): the input split at its NUL bytes, the first
//! part a batch manifest, the next (up to four) shards' results.json texts.
//!
//! - The manifest is parsed as `combustion batch` parses it (`Manifest::parse`, relative
//!   paths from a folder that does not exist, so a scene or environment file is never
//!   found). A refusal is one line within [`MAX_MESSAGE_BYTES`] with no number of more
//!   than 12 digits but the user's own text ([`check_message`]). An accepted manifest
//!   holds 1 to `MAX_JOBS` jobs in order, their names valid and unique without case;
//!   split into 2 and 3 shards (and, for up to 4 jobs, into one shard more than jobs),
//!   the shards deal out every job once; each shard's results as `batch --shard` writes them, given to the merge in
//!   reverse order, merge into every job once in the manifest's order, and the merged
//!   junit.xml is well-formed XML with one test case a job.
//! - The other parts are merged as `batch --merge` merges them: a refusal follows the
//!   message rule above; accepted results hold each job once, in order, its name valid,
//!   and their junit.xml is well-formed XML with one test case a job.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use combustion::cli::batch::MergedShards;
use combustion::cli::manifest::{check_name, text_digest, Manifest, Shard, MAX_JOBS};
use serde_json::json;

/// The longest refusal: a path whole (under 4,096 bytes: a longer value names no file
/// and is cut), a few echoed values, each cut to 40 characters, and the rule.
pub const MAX_MESSAGE_BYTES: usize = 4096 + 1024;

/// A folder that does not exist: the manifest's relative paths are taken from it.
const NO_FOLDER: &str = "/nonexistent/combustion-fuzz";

pub fn parse_and_merge(data: &[u8]) {
    let mut parts = data.split(|&b| b == 0);
    let manifest_text = String::from_utf8_lossy(parts.next().unwrap_or_default()).into_owned();
    let shards: Vec<(PathBuf, String)> = parts
        .take(4)
        .enumerate()
        .map(|(i, part)| {
            let folder = PathBuf::from(format!("shard-{i}"));
            (folder, String::from_utf8_lossy(part).into_owned())
        })
        .collect();
    manifest(&manifest_text);
    if !shards.is_empty() {
        merge(&shards);
    }
}

fn parse(text: &str) -> Result<Manifest, String> {
    Manifest::parse(text, Path::new(NO_FOLDER), "fuzz".into())
}

fn manifest(text: &str) {
    let manifest = match parse(text) {
        Ok(manifest) => manifest,
        Err(message) => return check_message(&message, &[text], true),
    };
    let jobs: Vec<(usize, String)> = manifest.jobs().map(|(i, n)| (i, n.to_owned())).collect();
    assert!((1..=MAX_JOBS).contains(&jobs.len()), "{} jobs", jobs.len());
    let mut names = HashSet::new();
    for (position, (index, name)) in jobs.iter().enumerate() {
        assert_eq!(*index, position, "job `{name}` out of order");
        check_name(name).unwrap_or_else(|e| panic!("an accepted job's name is refused: {e}"));
        assert!(names.insert(name.to_lowercase()), "`{name}` twice");
    }
    assert_eq!(manifest.digest(), text_digest(text));
    let mut counts = vec![2, 3];
    if jobs.len() <= 4 {
        counts.push(jobs.len() + 1);
    }
    for count in counts {
        let mut dealt = Vec::new();
        let mut results = Vec::new();
        for index in 1..=count {
            let mut share = parse(text).expect("the manifest parses again");
            share.keep_shard(Shard { index, count });
            let kept: Vec<(usize, String)> = share.jobs().map(|(i, n)| (i, n.to_owned())).collect();
            results.push((
                PathBuf::from(format!("shard-{index}")),
                shard_results(&share, Shard { index, count }),
            ));
            dealt.extend(kept);
        }
        dealt.sort();
        assert_eq!(dealt, jobs, "{count} shards do not deal out every job once");
        results.reverse();
        let merged = MergedShards::of(&results)
            .unwrap_or_else(|e| panic!("the shards' own results are refused: {e}"));
        let merged_jobs: Vec<(usize, String)> =
            merged.jobs().map(|(i, n)| (i, n.to_owned())).collect();
        assert_eq!(merged_jobs, jobs, "{count} shards merge into other jobs");
        assert_eq!(test_cases(&merged.junit()), jobs.len());
    }
}

/// A shard's results.json as `batch --shard` writes it, every job not rendered (the
/// format written here, apart from batch's writer: what the merge must read).
fn shard_results(share: &Manifest, shard: Shard) -> String {
    let jobs: Vec<_> = share
        .jobs()
        .map(|(index, name)| {
            json!({
                "index": index, "name": name, "scene": "builtin:spheres", "status": "error",
                "message": "not rendered", "seconds": 0.0, "outputs": [], "physics_error": null,
            })
        })
        .collect();
    json!({
        "manifest": "fuzz",
        "manifest_digest": share.digest(),
        "shard": {"index": shard.index, "count": shard.count},
        "seconds": 1.0,
        "jobs": jobs,
    })
    .to_string()
}

fn merge(shards: &[(PathBuf, String)]) {
    let merged = match MergedShards::of(shards) {
        Ok(merged) => merged,
        Err(message) => {
            let texts: Vec<&str> = shards.iter().map(|(_, text)| text.as_str()).collect();
            return check_message(&message, &texts, false);
        }
    };
    let jobs: Vec<(usize, &str)> = merged.jobs().collect();
    for pair in jobs.windows(2) {
        assert!(pair[0].0 < pair[1].0, "jobs {pair:?} out of order or twice");
    }
    for (_, name) in &jobs {
        check_name(name).unwrap_or_else(|e| panic!("a merged job's name is refused: {e}"));
    }
    let _ = merged.results_json().to_string();
    assert_eq!(test_cases(&merged.junit()), jobs.len());
}

/// The test cases of a JUnit text, which must be well-formed XML of XML 1.0's
/// characters (quick-xml's reader does not check those: U+FFFF broke CI readers once).
fn test_cases(xml: &str) -> usize {
    use quick_xml::events::Event;
    let xml_char = |c: char| matches!(c, '\t' | '\n' | '\r' | ' '..='\u{D7FF}' | '\u{E000}'..='\u{FFFD}' | '\u{10000}'..);
    if let Some(c) = xml.chars().find(|&c| !xml_char(c)) {
        panic!("junit.xml holds {:?}, not an XML 1.0 character", c);
    }
    let mut reader = quick_xml::Reader::from_str(xml);
    reader.config_mut().check_end_names = true;
    let mut cases = 0;
    loop {
        match reader.read_event() {
            Ok(Event::Eof) => return cases,
            Ok(Event::Start(e)) if e.name().as_ref() == b"testcase" => cases += 1,
            Ok(_) => {}
            Err(e) => panic!("junit.xml is not well-formed: {e}: {xml}"),
        }
    }
}

/// One line, within [`MAX_MESSAGE_BYTES`], no number of more than 12 digits but the
/// user's own text: a run of digits a string of `inputs` (any key or string value of
/// theirs that parses as JSON; the whole text of one that does not) holds — a name or path echoed, which may hold digits and
/// quotes of any kind — or, with `numbers_given`, one of their numbers (a manifest's
/// option value, echoed as given); not a number the message computed or read from
/// results (a shard index).
pub fn check_message(message: &str, inputs: &[&str], numbers_given: bool) {
    assert!(!message.is_empty(), "an empty message");
    assert!(
        !message.contains('\n'),
        "a message of more than one line: {message}"
    );
    assert!(
        message.len() <= MAX_MESSAGE_BYTES,
        "a message of {} bytes: {}",
        message.len(),
        message.chars().take(200).collect::<String>()
    );
    let mut texts = Vec::new();
    for input in inputs {
        match serde_json::from_str::<serde_json::Value>(input) {
            Ok(value) => strings_of(&value, numbers_given, &mut texts),
            // Not JSON: the message is the parser's, echoing the text itself.
            Err(_) => texts.push((*input).to_owned()),
        }
    }
    let digit_runs = message
        .split(|c: char| !c.is_ascii_digit())
        .filter(|run| run.len() > 12);
    for run in digit_runs {
        assert!(
            texts.iter().any(|t| t.contains(run)),
            "a number of more than 12 digits: {message}"
        );
    }
}

/// Every key and string value of `value` (and, with `numbers`, every number as written
/// back), into `out`.
fn strings_of(value: &serde_json::Value, numbers: bool, out: &mut Vec<String>) {
    match value {
        serde_json::Value::String(text) => out.push(text.clone()),
        serde_json::Value::Number(n) if numbers => out.push(n.to_string()),
        serde_json::Value::Array(items) => items.iter().for_each(|v| strings_of(v, numbers, out)),
        serde_json::Value::Object(fields) => {
            for (key, v) in fields {
                out.push(key.clone());
                strings_of(v, numbers, out);
            }
        }
        _ => {}
    }
}
