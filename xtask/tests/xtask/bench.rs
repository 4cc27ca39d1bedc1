//! Smoke test of `cargo xtask bench`'s measuring: the floor, the simulation and setup rows, one
//! repetition each, give a table with the expected columns. No timing is asserted.

use xtask::bench::{BenchOptions, run};

#[test]
fn smoke_run_gives_a_table_with_the_expected_columns() {
    let report = run(&BenchOptions::smoke()).expect("the smoke rows run");
    assert_eq!(report.rows[0].group, "floor");
    assert!(report.floor > 0.0);
    let names: Vec<&str> = report.rows.iter().map(|r| r.name.as_str()).collect();
    assert!(names.iter().any(|n| n.starts_with("exact")), "{names:?}");
    assert!(names.iter().any(|n| n.starts_with("ode45")), "{names:?}");
    assert!(
        names.iter().any(|n| n.starts_with("free decay")),
        "{names:?}"
    );
    assert!(
        names.iter().any(|n| n.starts_with("base excitation")),
        "{names:?}"
    );
    assert!(
        names
            .iter()
            .any(|n| n.starts_with("plan: configs/damper-test-machine.toml")),
        "{names:?}"
    );

    let md = report.markdown();
    assert!(
        md.contains("| group | row | median | min – max | × floor | reps | target | notes |"),
        "{md}"
    );
    assert!(md.contains("cores"), "{md}");
    let json = report.json();
    for key in [
        "date",
        "cores",
        "cpu",
        "load_average_start",
        "load_average_end",
        "rows",
    ] {
        assert!(json.get(key).is_some(), "{key} missing");
    }
    let row = &json["rows"][0];
    for key in [
        "median_s",
        "min_s",
        "max_s",
        "floor_multiple",
        "repetitions",
        "target_met",
    ] {
        assert!(row.get(key).is_some(), "{key} missing in {row}");
    }
    assert!(report.text().contains("bare 2-state recurrence"));
}
