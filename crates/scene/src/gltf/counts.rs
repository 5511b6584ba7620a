#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! The lengths of a glTF JSON's top-level arrays, counted before the document is parsed
//! into its tree: a pass that keeps nothing per element (serde's `IgnoredAny`), so a
//! file of millions of empty objects (`"nodes": [{}, {}, …]`, three bytes of JSON each,
//! hundreds of bytes parsed) is refused before its tree is built.

use serde::de::{Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::value::RawValue;

/// Most entries a top-level array of a glTF file may hold (nodes, accessors, materials,
/// …): the limit on what a scene places (2²¹).
pub(crate) const MAX_ARRAY_ENTRIES: u64 = 1 << 21;

/// glTF 2.0's top-level arrays: the ones counted (others, and `extras`, are the
/// application's, skipped as the parse skips them).
const GLTF_ARRAYS: [&str; 15] = [
    "accessors",
    "animations",
    "buffers",
    "bufferViews",
    "cameras",
    "extensionsRequired",
    "extensionsUsed",
    "images",
    "materials",
    "meshes",
    "nodes",
    "samplers",
    "scenes",
    "skins",
    "textures",
];

/// The first of glTF's top-level arrays in `json` with more than `limit` entries: its
/// name and how many it holds. `None` when every one is within the limit, or when
/// `json` is not a JSON object (the parse that follows says what is wrong).
pub(crate) fn array_over(json: &[u8], limit: u64) -> Option<(String, u64)> {
    let mut deserializer = serde_json::Deserializer::from_slice(json);
    deserializer
        .deserialize_map(TopLevel { limit })
        .ok()
        .flatten()
}

struct TopLevel {
    limit: u64,
}

impl<'de> Visitor<'de> for TopLevel {
    type Value = Option<(String, u64)>;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a glTF document")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        // The whole object read (serde_json checks it ends), the first array over kept.
        // Each value is skipped as the parse skips what it does not read (a number out
        // of f64's range or a lone surrogate in an application's value is no error
        // there), and only glTF's own arrays are counted, element by element.
        let mut over = None;
        while let Some(key) = map.next_key::<String>()? {
            let value = map.next_value::<&RawValue>()?;
            if over.is_some() || !GLTF_ARRAYS.contains(&key.as_str()) {
                continue;
            }
            let mut elements = serde_json::Deserializer::from_str(value.get());
            if let Ok(count) = elements.deserialize_seq(CountVisitor) {
                if count > self.limit {
                    over = Some((key, count));
                }
            }
        }
        Ok(over)
    }
}

/// An array's entries; nothing of them is kept.
struct CountVisitor;

impl<'de> Visitor<'de> for CountVisitor {
    type Value = u64;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("an array")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<u64, A::Error> {
        let mut count: u64 = 0;
        while seq.next_element::<IgnoredAny>()?.is_some() {
            count = count.saturating_add(1);
        }
        Ok(count)
    }
}

#[cfg(test)]
mod tests {
    use super::array_over;

    #[test]
    fn the_first_array_over_the_limit_is_named_with_its_length() {
        let json = br#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0,1,2,3]}],"nodes":[{},{},{}],"materials":[{},{},{},{}]}"#;
        // Nested arrays do not count (the scene's four node indices).
        assert_eq!(array_over(json, 3), Some(("materials".into(), 4)));
        assert_eq!(array_over(json, 2), Some(("nodes".into(), 3)));
        assert_eq!(array_over(json, 4), None);
        // Only glTF's own arrays count; values the parse skips are skipped alike.
        let json = br#"{"extras":[1,2,3,4],"x":1e400,"y":"\ud800","nodes":[{},{},{},{"z":1e400}]}"#;
        assert_eq!(array_over(json, 3), Some(("nodes".into(), 4)));
        // Not JSON, or not an object: the parse that follows reports it.
        assert_eq!(array_over(b"[1,2,3]", 0), None);
        assert_eq!(array_over(b"{\"nodes\":[{},", 0), None);
    }
}
