//! The speed-against-error report's CSV (`bench --report DIR` writes `report.csv` and
//! its companions; `bench --against DIR` reads an earlier `report.csv` back).
//!
//! One quoting rule both ways, the `csv` crate's: a field holding a comma, a double quote
//! or a line break is written in double quotes with `""` for a quote ([`Table`],
//! [`field`]), and [`records`] reads it back as written. [`PreviousReport::parse`] is the reader `--against` uses; it is a
//! crate of its own, with no renderer behind it, so the fuzz target `report_csv`
//! (fuzz/fuzz_targets/report_csv.rs) runs it from bytes.

use combustion_optics::shortened;

/// A writer of the report's CSV: one quoting rule for every field (the `csv` crate's:
/// a field holding a comma, a double quote or a line break in double quotes, `""` for
/// a quote), records ended by `\n`.
fn writer() -> csv::Writer<Vec<u8>> {
    csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .flexible(true)
        .from_writer(Vec::new())
}

/// The bytes a writer wrote, as text (what it was given was text).
fn written(writer: csv::Writer<Vec<u8>>) -> String {
    let bytes = writer
        .into_inner()
        .expect("writing to memory does not fail");
    String::from_utf8(bytes).expect("fields of text are written as text")
}

/// A CSV field as the report writes it: quoted when it holds `,`, `"` or a line break.
pub fn field(text: &str) -> String {
    let mut w = writer();
    // A lone empty field is written as `""` (not an empty line); the report writes it
    // among others, where it stands empty.
    w.write_record([text])
        .expect("writing to memory does not fail");
    let mut out = written(w);
    out.pop();
    if out == "\"\"" {
        out.clear();
    }
    out
}

/// A table the report writes: a header, then rows of fields ([`Table::row`]), as CSV
/// text ([`Table::finish`]).
pub struct Table {
    writer: csv::Writer<Vec<u8>>,
}

impl Table {
    /// A table of the columns `header`.
    pub fn new(header: &[&str]) -> Self {
        let mut writer = writer();
        writer
            .write_record(header)
            .expect("writing to memory does not fail");
        Self { writer }
    }

    /// Appends a row.
    pub fn row<I, F>(&mut self, fields: I)
    where
        I: IntoIterator<Item = F>,
        F: AsRef<[u8]>,
    {
        self.writer
            .write_record(fields)
            .expect("writing to memory does not fail");
    }

    /// The table's text.
    pub fn finish(self) -> String {
        written(self.writer)
    }
}

/// Splits CSV text into records of fields (the `csv` crate's reading: a field in double
/// quotes, `""` inside, line breaks inside kept): each record with the 1-based line it
/// starts on. `\n`, `\r\n` or `\r` ends a record outside quotes; empty lines are
/// skipped; records may have any number of fields.
pub fn records(text: &str) -> Vec<(usize, Vec<String>)> {
    record_iter(text).collect()
}

/// [`records`] one at a time, as the text is read: a reader of a long table holds one
/// record's fields at a time, not the table's.
pub fn record_iter(text: &str) -> impl Iterator<Item = (usize, Vec<String>)> + '_ {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut record = csv::StringRecord::new();
    // The line a record starts on: the line breaks before its first byte, plus one (a
    // break inside a quoted field counts, `\r\n` once).
    let (mut counted_to, mut line) = (0, 1);
    std::iter::from_fn(move || {
        // Text in, text out: a read fails only past the text's end (or never).
        while let Ok(true) = reader.read_record(&mut record) {
            // The reader's position may stand on the `\n` of the `\r\n` before the
            // record (or an empty line's): its first byte is the first after those.
            let mut start = record.position().map_or(0, |p| p.byte() as usize);
            while matches!(text.as_bytes().get(start), Some(b'\r' | b'\n')) {
                start += 1;
            }
            line += text.as_bytes()[counted_to..start]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            counted_to = start;
            let fields: Vec<String> = record.iter().map(str::to_owned).collect();
            if fields.len() > 1 || fields.first().is_some_and(|f| !f.is_empty()) {
                return Some((line, fields));
            }
        }
        None
    })
}

/// The columns that name a row of `report.csv`: the scene and the six of its variant set.
pub const KEY_COLUMNS: usize = 7;

/// The error columns `--against` compares as written, in this order.
pub const ERROR_COLUMNS: [&str; 4] = [
    "max_relative_error",
    "mean_relative_error",
    "rms_relative_error",
    "flip_mean",
];

/// Why an earlier `report.csv` cannot be read back.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReportCsvError {
    /// No record at all.
    #[error("empty")]
    Empty,
    /// The header lacks a column this reader needs.
    #[error("no `{0}` column (not a report.csv of this version)")]
    MissingColumn(&'static str),
    /// The header is shorter than the key.
    #[error("{0} columns; a report.csv starts with 7 naming the scene and variant set")]
    TooFewColumns(usize),
    /// A record whose field count differs from the header's.
    #[error("line {line} has {fields} fields, the header {header}")]
    FieldCount {
        /// The line the record starts on.
        line: usize,
        /// Its fields.
        fields: usize,
        /// The header's.
        header: usize,
    },
    /// A `total_ms` that is not a finite number above 0 (a ratio against it would not be
    /// a number).
    #[error("line {line}: total_ms `{value}` is not a frame time (a finite number of ms above 0)")]
    NotAFrameTime {
        /// The line the record starts on.
        line: usize,
        /// The field, shortened.
        value: String,
    },
}

/// One row of an earlier run: its key (the first seven columns joined by commas), its
/// total frame time and its error columns as written.
#[derive(Debug, Clone, PartialEq)]
pub struct PreviousRow {
    /// Scene and variant set, `KEY_COLUMNS` fields joined by `,`.
    pub key: String,
    /// Median total frame time, ms: finite and above 0.
    pub total_ms: f64,
    /// [`ERROR_COLUMNS`] as written.
    pub errors: [String; 4],
}

/// The rows of an earlier run's `report.csv`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PreviousReport {
    /// In the file's order.
    pub rows: Vec<PreviousRow>,
}

impl PreviousReport {
    /// Reads `report.csv` text: a header naming at least the key, `total_ms` and the
    /// error columns, then records of as many fields.
    pub fn parse(text: &str) -> Result<PreviousReport, ReportCsvError> {
        let mut records = records(text).into_iter();
        let (_, header) = records.next().ok_or(ReportCsvError::Empty)?;
        if header.len() < KEY_COLUMNS {
            return Err(ReportCsvError::TooFewColumns(header.len()));
        }
        let column = |name: &'static str| {
            header
                .iter()
                .position(|h| h == name)
                .ok_or(ReportCsvError::MissingColumn(name))
        };
        let total = column("total_ms")?;
        let errors = [
            column(ERROR_COLUMNS[0])?,
            column(ERROR_COLUMNS[1])?,
            column(ERROR_COLUMNS[2])?,
            column(ERROR_COLUMNS[3])?,
        ];
        let mut rows = Vec::new();
        for (line, fields) in records {
            if fields.len() != header.len() {
                return Err(ReportCsvError::FieldCount {
                    line,
                    fields: fields.len(),
                    header: header.len(),
                });
            }
            let total_ms = fields[total]
                .parse::<f64>()
                .ok()
                .filter(|ms| ms.is_finite() && *ms > 0.0)
                .ok_or_else(|| ReportCsvError::NotAFrameTime {
                    line,
                    value: shortened(&fields[total]),
                })?;
            rows.push(PreviousRow {
                key: fields[..KEY_COLUMNS].join(","),
                total_ms,
                errors: errors.map(|c| fields[c].clone()),
            });
        }
        Ok(PreviousReport { rows })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "scene,fresnel,hdr,pipeline,masking,distribution,diffuse,total_ms,max_relative_error,mean_relative_error,rms_relative_error,flip_mean";

    #[test]
    fn fields_written_with_the_reports_quoting_read_back_as_written() {
        let awkward = [
            "plain",
            "",
            "a,b",
            "say \"hi\"",
            "line\nbreak",
            "crlf\r\n",
            "lone\r",
            "\"",
            ",",
        ];
        let line: Vec<String> = awkward.iter().map(|f| field(f)).collect();
        let text = format!("{}\n{}", line.join(","), line.join(","));
        let read = records(&text);
        assert_eq!(read.len(), 2);
        assert_eq!(read[0].1, awkward);
        assert_eq!(read[1].1, awkward);
        // The second record starts after the quoted line breaks of the first.
        assert_eq!(read[1].0, 4);
        assert_eq!(field("plain"), "plain");
    }

    /// A table written with the `csv` crate reads back field for field, each record
    /// with the line it starts on (a quoted line break counts: the third record starts
    /// on line 4); a field holding U+FFFF or a comma stands as written.
    #[test]
    fn a_table_reads_back_as_written() {
        let mut table = Table::new(&["scene", "ms"]);
        table.row(["a\nb,\"c\"", "1.5"]);
        table.row(["\u{ffff}", ""]);
        let text = table.finish();
        let read = records(&text);
        assert_eq!(
            read,
            [
                (1, vec!["scene".to_owned(), "ms".to_owned()]),
                (2, vec!["a\nb,\"c\"".to_owned(), "1.5".to_owned()]),
                (4, vec!["\u{ffff}".to_owned(), String::new()]),
            ]
        );
    }

    #[test]
    fn a_report_reads_back_its_key_frame_time_and_error_columns() {
        let text = format!(
            "{HEADER}\r\n\"a,\"\"b\"\"\",full,f32,specialised,correlated,ggx,material,12.5,1e-3,1e-4,2e-4,5e-3\r\n\n"
        );
        let report = PreviousReport::parse(&text).unwrap();
        assert_eq!(
            report.rows,
            [PreviousRow {
                key: "a,\"b\",full,f32,specialised,correlated,ggx,material".into(),
                total_ms: 12.5,
                errors: ["1e-3", "1e-4", "2e-4", "5e-3"].map(String::from),
            }]
        );
    }

    #[test]
    fn a_report_that_is_not_one_is_refused_with_its_reason() {
        use ReportCsvError::*;
        assert_eq!(PreviousReport::parse(""), Err(Empty));
        assert_eq!(PreviousReport::parse("\n\r\n"), Err(Empty));
        assert_eq!(PreviousReport::parse("a,b,c\n"), Err(TooFewColumns(3)));
        assert_eq!(
            PreviousReport::parse("a,b,c,d,e,f,g,h\n"),
            Err(MissingColumn("total_ms"))
        );
        let without_flip = HEADER.trim_end_matches(",flip_mean");
        assert_eq!(
            PreviousReport::parse(without_flip),
            Err(MissingColumn("flip_mean"))
        );
        assert_eq!(
            PreviousReport::parse(&format!("{HEADER}\n\"x\ny\",1\n")),
            Err(FieldCount {
                line: 2,
                fields: 2,
                header: 12
            })
        );
        let long = "9".repeat(10_000);
        let row = format!("s,full,f32,specialised,correlated,ggx,material,-{long},1,1,1,1");
        let Err(NotAFrameTime { line, value }) = PreviousReport::parse(&format!("{HEADER}\n{row}"))
        else {
            panic!("a negative frame time was taken");
        };
        assert_eq!(line, 2);
        assert!(value.len() < 100, "{value}");
    }
}
