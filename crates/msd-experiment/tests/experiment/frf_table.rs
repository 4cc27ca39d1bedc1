//! The table `configs/frf-table.toml` reads is the one the `frf_table` example writes,
//! and the config fits it: m, c and k of the plant it was simulated on inside their
//! 95 % intervals.

use msd_experiment::config::Config;
use msd_experiment::frf::{self, FrfFit};

#[path = "../../examples/frf_table.rs"]
mod example;

const CONFIG: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../configs/frf-table.toml");

#[test]
fn the_shipped_table_is_what_the_example_writes() {
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../configs/data/stepped-sine-table.csv"
    );
    let text = std::fs::read_to_string(shipped).expect("the shipped file");
    assert!(
        text == example::stepped_sine_table(),
        "configs/data/stepped-sine-table.csv differs: run the example again"
    );
}

#[test]
fn the_table_config_fits_the_plant_it_was_simulated_on() {
    let config = Config::load(CONFIG.as_ref()).expect("valid");
    let outcome = frf::run(config, CONFIG.as_ref(), &Default::default()).expect("fits");
    assert_eq!(outcome.data.frequency.len(), 30);
    assert!(outcome.time_domain.is_none(), "a table has no time records");
    let FrfFit::OneMode(fit) = &outcome.fit else {
        panic!("one mode")
    };
    let u = &fit.uncertainty;
    for (name, interval, truth) in [
        ("m", u.mass, 2.5),
        ("c", u.damping, 1.8),
        ("k", u.stiffness, 120.0),
    ] {
        assert!(interval.contains(truth), "{name}: {interval:?}");
    }
}
