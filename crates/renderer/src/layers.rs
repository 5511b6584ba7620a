//! The renderer's layers (docs/architecture.md, "Inside the renderer"), checked: every
//! module of crates/renderer/src belongs to one, and no module imports one of a layer
//! above its own. Read from the sources: each `crate::NAME` a module names (outside its
//! tests, its comments and its `#[cfg(doc)]` imports, which only make doc links), NAME
//! a module or an item the crate root re-exports from one; an item of the root itself
//! (`Renderer`) is the top layer's.

use std::collections::BTreeMap;
use std::path::Path;

/// The layers, bottom to top, and their modules (`passes` holds passes/*.rs; `lib` is
/// the crate root). A module may import its own layer and those below.
const LAYERS: &[(&str, &[&str])] = &[
    (
        "resources",
        &[
            "accel",
            "bindings",
            "buffers",
            "color",
            "commands",
            "compute",
            "deform",
            "environment",
            "environment_importance",
            "error",
            "exposure",
            "fullscreen",
            "gbuffer",
            "gpu_types",
            "graph",
            "host",
            "light_cull",
            "mesh_draw",
            "offscreen",
            "options",
            "overlay",
            "pass_io",
            "pipelines",
            "push",
            "placeholders",
            "placement",
            "results",
            "retire",
            "scene_edit",
            "scene_upload",
            "shader_sources",
            "shadows",
            "shared",
            "slot",
            "spirv",
            "targets",
            "textures",
            "variant",
        ],
    ),
    ("passes", &["passes"]),
    ("renderer", &["lib", "frame"]),
];

/// The f64 per-pixel reference: beside the frame, not in it. It may import the
/// resources layer; no module imports it.
const REFERENCE: &str = "reference";

/// This check itself (a test module: it imports nothing).
const CHECK: &str = "layers";

/// The source of each module, by module name, without its tests, comments and
/// `#[cfg(doc)]` imports.
fn sources(root: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let mut read = |dir: &Path, module_of: &dyn Fn(&str) -> String| {
        for entry in std::fs::read_dir(dir).expect("the source directory") {
            let path = entry.expect("an entry").path();
            if path.extension().is_some_and(|e| e == "rs") {
                let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
                let text = std::fs::read_to_string(&path).expect("a source file");
                out.entry(module_of(&stem))
                    .or_insert_with(String::new)
                    .push_str(&code_of(&text));
            }
        }
    };
    read(root, &|stem| stem.to_owned());
    read(&root.join("passes"), &|_| "passes".to_owned());
    out
}

/// `text` without its `#[cfg(test)] mod tests`, its comments and its `#[cfg(doc)]`
/// imports.
fn code_of(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => text,
    };
    let mut code = String::new();
    let mut doc_only = false;
    for line in text.lines() {
        let line = line.split("//").next().unwrap_or("");
        if line.trim() == "#[cfg(doc)]" {
            doc_only = true;
            continue;
        }
        if doc_only {
            // The import the attribute applies to, up to its `;`.
            doc_only = !line.contains(';');
            continue;
        }
        code.push_str(line);
        code.push('\n');
    }
    code
}

/// The first path segment of every `crate::…` the code names.
fn named(code: &str) -> Vec<String> {
    let mut names = Vec::new();
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            // The group's top-level items (a nested `a::{b, c}` is one item, `a`).
            let (mut depth, mut item) = (0usize, String::new());
            for c in group.chars() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        names.extend(first_segment(&item));
                        item.clear();
                        continue;
                    }
                    _ => {}
                }
                item.push(c);
            }
            names.extend(first_segment(&item));
        } else {
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            names.push(rest[..end].to_owned());
        }
    }
    names
}

/// The first path segment of one item of a `use` group (`a::b` → `a`), if any.
fn first_segment(item: &str) -> Option<String> {
    let first = item.trim().split("::").next().unwrap_or("").trim();
    (!first.is_empty()).then(|| first.to_owned())
}

/// The module each item the crate root re-exports comes from (`pub use module::{…}`,
/// `pub use module::Item;`).
fn re_exports(root_code: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for (i, _) in root_code.match_indices("pub use ") {
        let rest = &root_code[i + "pub use ".len()..];
        let statement = &rest[..rest.find(';').unwrap_or(rest.len())];
        let Some((module, items)) = statement.split_once("::") else {
            continue;
        };
        let items = items.trim().trim_start_matches('{').trim_end_matches('}');
        for item in items.split(',') {
            let item = item.trim();
            if !item.is_empty() {
                out.insert(item.to_owned(), module.trim().to_owned());
            }
        }
    }
    out
}

/// The layer index of `module` (the reference's: none), or a failure for a module no
/// layer lists.
fn layer_of(module: &str) -> Option<usize> {
    LAYERS
        .iter()
        .position(|(_, modules)| modules.contains(&module))
}

/// Every import that reaches above its module's layer, or at the reference, as
/// "module imports name (layer)" lines.
fn upward_imports(sources: &BTreeMap<String, String>) -> Vec<String> {
    let exports = re_exports(&sources["lib"]);
    let mut found = Vec::new();
    for (module, code) in sources {
        if module == CHECK {
            continue;
        }
        let own = if module == REFERENCE {
            0
        } else {
            layer_of(module).unwrap_or_else(|| {
                panic!("module {module} is in no layer: place it in LAYERS (layers.rs) and docs/architecture.md")
            })
        };
        for name in named(code) {
            let target = if sources.contains_key(&name) {
                name.clone()
            } else {
                // An item of the root: re-exported from a module, or its own.
                exports
                    .get(&name)
                    .cloned()
                    .unwrap_or_else(|| "lib".to_owned())
            };
            if target == *module || target == CHECK {
                continue;
            }
            if target == REFERENCE {
                found.push(format!("{module} imports {name} (the reference)"));
                continue;
            }
            let layer = layer_of(&target).expect("every module is placed (checked above)");
            if layer > own {
                found.push(format!(
                    "{module} ({}) imports {name} ({})",
                    if module == REFERENCE {
                        REFERENCE
                    } else {
                        LAYERS[own].0
                    },
                    LAYERS[layer].0
                ));
            }
        }
    }
    found
}

#[test]
fn no_module_imports_a_layer_above_its_own() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let sources = sources(&root);
    assert!(sources.len() > 30, "{:?}", sources.keys());
    let upward = upward_imports(&sources);
    assert!(
        upward.is_empty(),
        "imports above their layer (docs/architecture.md, \"Inside the renderer\"):\n{}",
        upward.join("\n")
    );
}

/// The check sees what it must: an import of the crate root's `Renderer` from a
/// resource module, of the frame from a pass, of the reference from anywhere, and of a
/// root re-export by its module's layer.
#[test]
fn the_layer_check_finds_upward_imports() {
    let mut sources: BTreeMap<String, String> = [
        (
            "lib",
            "pub use gbuffer::{GBufferPass, DEPTH_FORMAT};\npub struct Renderer;",
        ),
        ("frame", "use crate::passes::FRAME;"),
        (
            "passes",
            "use crate::frame::record;\nuse crate::{gbuffer, Renderer};",
        ),
        (
            "gbuffer",
            "use crate::{bindings::{self, SetDecl}, DEPTH_FORMAT};",
        ),
        (
            "bindings",
            "// use crate::Renderer;\nuse crate::reference::x;",
        ),
        (
            "reference",
            "#[cfg(doc)]\nuse crate::Renderer;\nuse crate::GBufferPass;",
        ),
    ]
    .into_iter()
    .map(|(m, code)| (m.to_owned(), code_of(code)))
    .collect();
    let upward = upward_imports(&sources);
    assert_eq!(
        upward,
        [
            "bindings imports reference (the reference)",
            "passes (passes) imports frame (renderer)",
            "passes (passes) imports Renderer (renderer)",
        ],
        "{upward:?}"
    );
    sources.insert("gbuffer".into(), code_of("use crate::Renderer;"));
    assert!(upward_imports(&sources)
        .contains(&"gbuffer (resources) imports Renderer (renderer)".to_owned()));
}
