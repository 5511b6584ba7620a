//! What the crate's tests and its `memory_bounds` example share (the example includes
//! this file by path; each uses a part of it): fresh temporary folders, the peak memory
//! a piece of work adds, and the smallest glTF files the memory and resource cases use.
#![allow(dead_code)]

use std::path::PathBuf;

/// A fresh, empty temporary folder for this process, named `group`-`name`.
pub fn temp_dir(group: &str, name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("combustion-{group}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// A field of /proc/self/status in bytes (`VmRSS`, `VmHWM`).
pub fn status_bytes(field: &str) -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("/proc/self/status");
    status
        .lines()
        .find_map(|l| l.strip_prefix(field)?.strip_prefix(':'))
        .and_then(|v| v.trim().trim_end_matches(" kB").trim().parse::<u64>().ok())
        .map(|kib| kib * 1024)
        .unwrap_or_else(|| panic!("{field} in /proc/self/status"))
}

/// The rise of this process's peak resident memory while `f` runs, over its resident
/// memory just before (Linux ≥ 4.0: the peak is reset through /proc/self/clear_refs).
pub fn peak_rise<T>(f: impl FnOnce() -> T) -> (T, u64) {
    std::fs::write("/proc/self/clear_refs", "5").expect("reset the peak (/proc/self/clear_refs)");
    let before = status_bytes("VmRSS");
    let out = f();
    let peak = status_bytes("VmHWM");
    (out, peak.saturating_sub(before))
}

/// One triangle's accessor, view and buffer (36 bytes of positions as a data URI), as
/// the members of a glTF document's top-level object.
pub const TRIANGLE: &str = r#""accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],"bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]"#;

/// A glTF document of one triangle whose material's base colour is the image at
/// `image_uri`.
pub fn textured_triangle(image_uri: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"material":0}}]}}],"materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],"textures":[{{"source":0}}],"images":[{{"uri":"{image_uri}"}}],{TRIANGLE}}}"#
    )
}

/// A glTF document of `side` nodes, each placing one mesh of `side` primitives (all the
/// same triangle): `side`² placements from a few bytes of JSON each.
pub fn placements(side: usize) -> String {
    let list = |item: &dyn Fn(usize) -> String| (0..side).map(item).collect::<Vec<_>>().join(",");
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{}],"meshes":[{{"primitives":[{}]}}],{TRIANGLE}}}"#,
        list(&|i| i.to_string()),
        list(&|i| format!(r#"{{"mesh":0,"translation":[{i},0,0]}}"#)),
        list(&|_| r#"{"attributes":{"POSITION":0}}"#.into()),
    )
}
