//! TOML round trips: the paper's inputs (and the snippets in the docs), every kind,
//! unknown fields rejected.

use msd_signal::{
    ClippingOptions, LineSelection, Multisine, MultisineSpec, PhaseScheme, Prbs, PrbsSpec, Signal,
    Sweep, paper_identification_input, paper_validation_input,
};

fn round_trip(s: &Signal) -> Signal {
    let text = toml::to_string(s).expect("serialisable");
    toml::from_str(&text).unwrap_or_else(|e| panic!("re-parse failed: {e}\n{text}"))
}

/// The ```toml blocks of the paper module's docs.
fn doc_snippets() -> Vec<String> {
    let src = include_str!("../../src/paper.rs");
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in src.lines() {
        let body = line
            .trim_start()
            .strip_prefix("//!")
            .map(|l| l.strip_prefix(' ').unwrap_or(l));
        let Some(body) = body else { continue };
        match (&mut current, body.trim()) {
            (None, "```toml") => current = Some(String::new()),
            (Some(b), "```") => {
                blocks.push(std::mem::take(b));
                current = None;
            }
            (Some(b), _) => {
                b.push_str(body);
                b.push('\n');
            }
            (None, _) => {}
        }
    }
    blocks
}

#[test]
fn paper_inputs_round_trip_and_match_the_documented_snippets() {
    let id = paper_identification_input();
    let val = paper_validation_input();
    assert_eq!(round_trip(&id), id);
    assert_eq!(round_trip(&val), val);
    let snippets = doc_snippets();
    assert_eq!(snippets.len(), 2);
    let parsed_id: Signal = toml::from_str(&snippets[0]).expect("identification snippet parses");
    let parsed_val: Signal = toml::from_str(&snippets[1]).expect("validation snippet parses");
    assert_eq!(parsed_id, id);
    assert_eq!(parsed_val, val);
    // And they give the documented values after the trip.
    let back = round_trip(&id);
    for i in 0..7501 {
        let t = i as f64 * 0.002;
        assert_eq!(back.value(t), id.value(t));
    }
    assert_eq!(back.value(0.5), 6.0);
}

#[test]
fn every_kind_round_trips() {
    let ms = Multisine::new(MultisineSpec {
        phases: PhaseScheme::Random,
        lines: LineSelection::RandomOdd,
        seed: 17,
        crest_factor_reduction: Some(ClippingOptions {
            iterations: 5,
            clip_ratio: 0.8,
        }),
        ..MultisineSpec::default()
    })
    .expect("valid");
    let prbs = Prbs::new(PrbsSpec {
        order: 7,
        clock_period: 0.02,
        amplitude: 0.5,
        t_start: 1.0,
    })
    .expect("valid");
    let all = Signal::Sum {
        terms: vec![
            Signal::Constant { value: 0.25 },
            Signal::Sine {
                amplitude: 1.0,
                frequency: 2.0,
                phase: 0.1,
                t_on: 0.5,
                t_off: Some(3.0),
            },
            Signal::Chirp {
                amplitude: 1.0,
                f0: 0.1,
                f1: 10.0,
                duration: 5.0,
                phase: 0.0,
                sweep: Sweep::Logarithmic,
                t_start: 1.0,
            },
            Signal::Multisine(ms.clone()),
            Signal::Prbs(prbs),
            Signal::Step {
                amplitude: 1.0,
                time: 2.0,
            }
            .scaled(-2.0),
        ],
    };
    let back = round_trip(&all);
    assert_eq!(back, all);
    // The multisine is rebuilt identically (same seed → same lines and phases).
    let Signal::Sum { terms } = &back else {
        panic!("a sum")
    };
    let Signal::Multisine(ms2) = &terms[3] else {
        panic!("a multisine")
    };
    assert_eq!(ms2.harmonics(), ms.harmonics());
    assert_eq!(ms2.phases(), ms.phases());
    for &t in &[0.0, 0.7, 1.3, 2.9, 4.4] {
        assert_eq!(back.value(t), all.value(t));
    }
}

#[test]
fn defaults_apply_and_unknown_fields_are_rejected() {
    let s: Signal = toml::from_str("kind = \"sine\"\namplitude = 2\nfrequency = 1.5\n")
        .expect("defaults fill in");
    assert_eq!(
        s,
        Signal::Sine {
            amplitude: 2.0,
            frequency: 1.5,
            phase: 0.0,
            t_on: 0.0,
            t_off: None
        }
    );
    let r: Result<Signal, _> =
        toml::from_str("kind = \"step\"\namplitude = 1.0\ntime = 0.5\ncolour = 3\n");
    assert!(r.is_err(), "unknown field in a struct variant");
    let r: Result<Signal, _> = toml::from_str(
        "kind = \"prbs\"\norder = 5\nclock_period = 0.1\namplitude = 1.0\nextra = 1\n",
    );
    assert!(r.is_err(), "unknown field in a prbs");
    let r: Result<Signal, _> = toml::from_str("kind = \"wobble\"\n");
    assert!(r.is_err(), "unknown kind");
    // Deserialising a multisine or PRBS validates it.
    let r: Result<Signal, _> =
        toml::from_str("kind = \"prbs\"\norder = 40\nclock_period = 0.1\namplitude = 1.0\n");
    let msg = r.expect_err("order 40 is out of range").to_string();
    assert!(msg.contains("PRBS order 40"), "{msg}");
}

#[test]
fn welch_options_from_toml() {
    use msd_signal::{Detrend, WelchOptions, Window};
    let o: WelchOptions =
        toml::from_str("segment_length = 512\ndetrend = \"linear\"\n").expect("parses");
    assert_eq!(
        o,
        WelchOptions {
            segment_length: Some(512),
            overlap: 0.5,
            window: Window::Auto,
            detrend: Detrend::Linear
        }
    );
    assert_eq!(
        toml::from_str::<WelchOptions>("").expect("all defaults"),
        WelchOptions::default()
    );
    assert!(toml::from_str::<WelchOptions>("segments = 3\n").is_err());
}
