//! The `output` section: cadences, formats, encoding and columns, and their errors.

use super::*;
use crate::{OutputFormat, VtkEncoding};

fn with_output(output: &str) -> String {
    edit(&[(
        "end_time: 1.0,",
        &format!("end_time: 1.0, output: {output},"),
    )])
}

#[test]
fn a_time_cadence_may_keep_the_default_step_cadence_or_zero() {
    for output in [
        "(snapshot_dt: 0.1)",
        "(snapshot_dt: Some(0.1), snapshot_every: 200)",
        "(snapshot_dt: 0.1, snapshot_every: 0)",
    ] {
        let s = load(&with_output(output)).unwrap();
        assert_eq!(s.output.snapshot_dt, Some(0.1), "{output}");
    }
    let s = load(&with_output(
        "(formats: [], vtk_encoding: Ascii, columns: None)",
    ))
    .unwrap();
    assert!(s.output.formats.is_empty());
    assert!(!s.output.writes(OutputFormat::Csv));
    assert_eq!(s.output.vtk_encoding, VtkEncoding::Ascii);
}

#[test]
fn both_cadences_are_refused_as_ambiguous() {
    let (field, message) = invalid(&with_output("(snapshot_every: 50, snapshot_dt: 0.1)"));
    assert_eq!(field, "output.snapshot_dt");
    assert!(message.contains("ambiguous"), "{message}");
    assert!(
        message.contains("50 steps") && message.contains("0.1 s"),
        "{message}"
    );
}

#[test]
fn bad_output_values_are_refused_where_they_stand() {
    for (output, at, want) in [
        (
            "(snapshot_dt: 0.0)",
            "0.0)",
            "snapshot_dt must be a finite number of seconds > 0",
        ),
        ("(snapshot_dt: -1.5)", "-1.5", "got -1.5"),
        ("(snapshot_dt: inf)", "inf", "got inf"),
        ("(formats: [Csv, Hdf5])", "Hdf5", "Hdf5"),
        (
            "(formats: [Vtk, Csv, Vtk])",
            "Vtk])",
            "formats lists Vtk twice",
        ),
        ("(vtk_encoding: Base64)", "Base64", "Base64"),
        (
            "(columns: [\"pressure\", \"pressure\"])",
            "\"pressure\"])",
            "columns lists \"pressure\" twice",
        ),
        ("(columns: [\"\"])", "\"\"", "empty name"),
        ("(vtk: true)", "vtk:", "vtk"),
    ] {
        let text = with_output(output);
        let (line, col, msg) = parse_error(&text);
        assert!(msg.contains(want), "{output}: {msg}");
        let (l, c) = line_col(&text, at);
        assert_eq!(line, l, "{output}: {msg}");
        assert!(
            col <= c + at.len(),
            "{output}: column {col}, value at {c}: {msg}"
        );
    }
}
