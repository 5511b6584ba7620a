#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! The lengths of a glTF JSON's top-level arrays, counted before the document is parsed
//! into its tree: a pass that keeps nothing per element (serde's `IgnoredAny`), so a
//! file of millions of empty objects (`"nodes": [{}, {}, …]`, three bytes of JSON each,
//! hundreds of bytes parsed) is refused before its tree is built.

use serde::de::{Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};

/// Most entries a top-level array of a glTF file may hold (nodes, accessors, materials,
/// …): the limit on what a scene places (2²¹).
pub(crate) const MAX_ARRAY_ENTRIES: u64 = 1 << 21;

/// The first top-level array of `json` with more than `limit` entries: its name and how
/// many it holds (counted to the end). `None` when every array is within the limit, or
/// when `json` is not a JSON object (the parse that follows says what is wrong).
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
        let mut over = None;
        while let Some(key) = map.next_key::<String>()? {
            let count = map.next_value::<Count>()?.0;
            if over.is_none() && count > self.limit {
                over = Some((key, count));
            }
        }
        Ok(over)
    }
}

/// A value's entries if it is an array, else 0; nothing of it is kept.
struct Count(u64);

impl<'de> serde::Deserialize<'de> for Count {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(CountVisitor).map(Count)
    }
}

struct CountVisitor;

impl<'de> Visitor<'de> for CountVisitor {
    type Value = u64;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<u64, A::Error> {
        let mut count: u64 = 0;
        while seq.next_element::<IgnoredAny>()?.is_some() {
            count = count.saturating_add(1);
        }
        Ok(count)
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<u64, A::Error> {
        while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
        Ok(0)
    }
    fn visit_bool<E>(self, _: bool) -> Result<u64, E> {
        Ok(0)
    }
    fn visit_i64<E>(self, _: i64) -> Result<u64, E> {
        Ok(0)
    }
    fn visit_u64<E>(self, _: u64) -> Result<u64, E> {
        Ok(0)
    }
    fn visit_f64<E>(self, _: f64) -> Result<u64, E> {
        Ok(0)
    }
    fn visit_str<E>(self, _: &str) -> Result<u64, E> {
        Ok(0)
    }
    fn visit_unit<E>(self) -> Result<u64, E> {
        Ok(0)
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
        // Not JSON, or not an object: the parse that follows reports it.
        assert_eq!(array_over(b"[1,2,3]", 0), None);
        assert_eq!(array_over(b"{\"nodes\":[{},", 0), None);
    }
}
