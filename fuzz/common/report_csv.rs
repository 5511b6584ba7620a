//! What the `report_csv` fuzz target does with one input, shared with the test that
//! replays the committed corpus (crates/report-csv/tests/fuzz_corpus.rs).

use combustion_report_csv::{field, records, PreviousReport};

/// `bench --against`'s reader of an earlier `report.csv`: every report it accepts has
/// frame times that are finite and above 0 and keys of seven fields; and any text's
/// records, written back with the report's quoting, read back as the same records.
pub fn parse_and_round_trip(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(report) = PreviousReport::parse(text) {
        for row in &report.rows {
            assert!(row.total_ms.is_finite() && row.total_ms > 0.0, "{row:?}");
        }
    }
    let read = records(text);
    let written: String = read
        .iter()
        .map(|(_, fields)| {
            let fields: Vec<String> = fields.iter().map(|f| field(f)).collect();
            fields.join(",") + "\n"
        })
        .collect();
    let again = records(&written);
    let fields = |r: &[(usize, Vec<String>)]| r.iter().map(|(_, f)| f.clone()).collect::<Vec<_>>();
    assert_eq!(fields(&read), fields(&again), "written back as {written:?}");
}
