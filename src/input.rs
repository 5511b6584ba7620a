//! Reading the command line's input files — spectral tables, an earlier report, camera
//! paths — by the rule the glTF importer keeps for every file it reads
//! ([`combustion_scene::read_regular_file`]): a regular file (after symlinks) within a
//! size limit, both checked before any byte is read, so a FIFO never blocks and
//! `/dev/zero` is never read without end; then UTF-8 text.

/// The largest spectral table (`--csv`) read: 16 MiB (a table of every nanometre from
/// 450 to 740 nm takes a few KB).
pub const MAX_TABLE_BYTES: u64 = 16 << 20;
/// The largest earlier `report.csv` read (`bench --against`): 64 MiB.
pub const MAX_REPORT_BYTES: u64 = 64 << 20;
/// The largest camera path read (`view --camera-path`): 16 MiB.
pub use combustion_scene::MAX_CAMERA_PATH_BYTES;
/// The largest criteria file read (`diff --criteria-file`): 1 MiB.
pub const MAX_CRITERIA_BYTES: u64 = 1 << 20;

/// Reads `path` as UTF-8 text under the rule above (the scene crate's, beside
/// [`combustion_scene::read_regular_file`]).
pub use combustion_scene::read_text;

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("combustion-input-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A FIFO is refused without being opened (opening it would block until a writer
    /// came), a link to /dev/zero without being read, a file over the limit and bytes
    /// that are not UTF-8 with a message; a small text file is read.
    #[test]
    fn only_regular_text_files_within_the_limit_are_read() {
        let dir = scratch("rule");
        let fifo = dir.join("pipe.csv");
        assert!(std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success());
        let zero = dir.join("zero.csv");
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        let big = dir.join("big.csv");
        std::fs::write(&big, vec![b'1'; 101]).unwrap();
        let binary = dir.join("binary.csv");
        std::fs::write(&binary, [b'a', 0xff, b'b']).unwrap();
        let good = dir.join("good.csv");
        std::fs::write(&good, "500,1,2\n").unwrap();
        for (path, expected) in [
            (&fifo, "not a regular file"),
            (&zero, "not a regular file"),
            (
                &big,
                "101 bytes is more than the 100 bytes a test file may have",
            ),
            (&binary, "not UTF-8 text (invalid byte at offset 1)"),
        ] {
            let error = read_text(path, 100, "a test file").unwrap_err();
            assert!(error.contains(expected), "{}: {error}", path.display());
        }
        assert_eq!(read_text(&good, 100, "a test file").unwrap(), "500,1,2\n");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// JSON `text` parsed into a value, refusing an object that holds a key twice (serde_json
/// keeps the last one without a word: a manifest with two `"jobs"` rendered the second).
/// Every JSON the command line reads (batch manifests, shards' results) goes through it.
pub fn parse_json(text: &str) -> Result<serde_json::Value, String> {
    use serde::de::{Deserialize, Deserializer, Error as _, MapAccess, SeqAccess, Visitor};
    use serde_json::{Map, Value};

    struct Strict(Value);
    struct StrictVisitor;

    impl<'de> Deserialize<'de> for Strict {
        fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
            deserializer.deserialize_any(StrictVisitor).map(Strict)
        }
    }

    impl<'de> Visitor<'de> for StrictVisitor {
        type Value = Value;

        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("a JSON value")
        }
        fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
            Ok(Value::Bool(v))
        }
        fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
            Ok(Value::from(v))
        }
        fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
            Ok(Value::from(v))
        }
        fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
            Ok(Value::from(v))
        }
        fn visit_str<E>(self, v: &str) -> Result<Value, E> {
            Ok(Value::String(v.to_owned()))
        }
        fn visit_string<E>(self, v: String) -> Result<Value, E> {
            Ok(Value::String(v))
        }
        fn visit_unit<E>(self) -> Result<Value, E> {
            Ok(Value::Null)
        }
        fn visit_none<E>(self) -> Result<Value, E> {
            Ok(Value::Null)
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
            let mut values = Vec::new();
            while let Some(Strict(value)) = seq.next_element()? {
                values.push(value);
            }
            Ok(Value::Array(values))
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
            let mut object = Map::new();
            while let Some(key) = map.next_key::<String>()? {
                if object.contains_key(&key) {
                    return Err(A::Error::custom(format!(
                        "the key `{}` appears twice in one object",
                        crate::shortened(&key)
                    )));
                }
                let Strict(value) = map.next_value()?;
                object.insert(key, value);
            }
            Ok(Value::Object(object))
        }
    }

    serde_json::from_str::<Strict>(text)
        .map(|Strict(value)| value)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod json_tests {
    use super::parse_json;

    #[test]
    fn a_key_twice_in_one_object_is_refused() {
        let refused = parse_json(r#"{"jobs": [1], "jobs": [2]}"#).unwrap_err();
        assert!(
            refused.contains("the key `jobs` appears twice in one object"),
            "{refused}"
        );
        let nested = parse_json(r#"{"jobs": [{"name": "a", "name": "b"}]}"#).unwrap_err();
        assert!(nested.contains("the key `name` appears twice"), "{nested}");
        // The same key in two objects is no duplicate; values come back as serde_json reads them.
        let text = r#"{"a": {"k": 1.5}, "b": {"k": [true, null, "x", -3, 18446744073709551615]}}"#;
        assert_eq!(
            parse_json(text).unwrap(),
            serde_json::from_str::<serde_json::Value>(text).unwrap()
        );
    }
}
