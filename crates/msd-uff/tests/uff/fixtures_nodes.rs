//! The nodes (15, 2411) and data at nodes (55) of the pyuff fixtures, compared bit for bit
//! with what pyuff 2.5.8 reads from the same files (the JSON beside them).

use msd_uff::{Analysis55, Data55, Node, Precision};
use serde_json::Value;

use crate::fixtures::{int, real, reals, same_bits, text};

fn ints(v: &Value) -> Vec<i64> {
    v.as_array().expect("a list").iter().map(int).collect()
}

/// `count` nodes read from one dataset 15 or 2411 (`number`), against pyuff's.
pub(crate) fn check_nodes(nodes: &[Node], number: i64, d: &Value, what: &str) {
    let labels: Vec<i64> = nodes.iter().map(|n| n.label).collect();
    assert_eq!(labels, ints(&d["node_nums"]), "{what}");
    let field = |f: fn(&Node) -> i32| nodes.iter().map(|n| i64::from(f(n))).collect::<Vec<_>>();
    assert_eq!(field(|n| n.definition_cs), ints(&d["def_cs"]), "{what}");
    assert_eq!(field(|n| n.displacement_cs), ints(&d["disp_cs"]), "{what}");
    assert_eq!(field(|n| n.color), ints(&d["color"]), "{what}");
    let xyz: [fn(&Node) -> f64; 3] = [|n| n.x, |n| n.y, |n| n.z];
    for (get, key) in xyz.iter().zip(["x", "y", "z"]) {
        let ours: Vec<f64> = nodes.iter().map(get).collect();
        same_bits(&ours, &reals(&d[key]), &format!("{what} {key}"));
    }
    let precision = if number == 15 {
        Precision::Single
    } else {
        Precision::Double
    };
    assert!(nodes.iter().all(|n| n.precision == precision), "{what}");
}

/// One dataset 55 against pyuff's.
pub(crate) fn check_data55(ours: &Data55, d: &Value, what: &str) {
    let ids: Vec<&str> = ["id1", "id2", "id3", "id4", "id5"]
        .iter()
        .map(|k| text(&d[k]))
        .collect();
    assert_eq!(ours.ids.to_vec(), ids, "{what}");
    let record6 = [
        ours.model_type,
        ours.analysis.code(),
        ours.data_characteristic,
        ours.specific_data_type,
        if ours.complex { 5 } else { 2 },
    ]
    .map(i64::from);
    let keys = [
        "model_type",
        "analysis_type",
        "data_ch",
        "spec_data_type",
        "data_type",
    ];
    assert_eq!(record6, keys.map(|k| int(&d[k])), "{what}");
    assert_eq!(
        ours.values_per_node as i64,
        int(&d["n_data_per_node"]),
        "{what}"
    );
    let pair = |k: &str| {
        let v = reals(&d[k]);
        (v[0], v[1])
    };
    match &ours.analysis {
        Analysis55::NormalMode {
            load_case,
            mode,
            frequency,
            modal_mass,
            viscous_damping,
            hysteretic_damping,
        } => {
            assert_eq!(
                (*load_case, *mode),
                (int(&d["load_case"]), int(&d["mode_n"]))
            );
            same_bits(
                &[
                    *frequency,
                    *modal_mass,
                    *viscous_damping,
                    *hysteretic_damping,
                ],
                &["freq", "modal_m", "modal_damp_vis", "modal_damp_his"].map(|k| real(&d[k])),
                what,
            );
        }
        Analysis55::ComplexEigenvalue {
            load_case,
            mode,
            eigenvalue,
            modal_a,
            modal_b,
            ..
        } => {
            assert_eq!(
                (*load_case, *mode),
                (int(&d["load_case"]), int(&d["mode_n"]))
            );
            for (ours, key) in [
                (eigenvalue, "eig"),
                (modal_a, "modal_a"),
                (modal_b, "modal_b"),
            ] {
                let (re, im) = pair(key);
                same_bits(&[ours.0, ours.1], &[re, im], &format!("{what} {key}"));
            }
        }
        Analysis55::FrequencyResponse {
            load_case,
            frequency_step,
            frequency,
        } => {
            assert_eq!(
                (*load_case, *frequency_step),
                (int(&d["load_case"]), int(&d["freq_step_n"]))
            );
            same_bits(&[*frequency], &[real(&d["freq"])], what);
        }
        other => panic!("{what}: pyuff reads no parameters of {other:?}"),
    }
    assert_eq!(ours.nodes, ints(&d["node_nums"]), "{what}");
    for j in 0..ours.values_per_node {
        let key = format!("r{}", j + 1);
        let theirs = d[&key].as_array().expect("a list per node");
        assert_eq!(theirs.len(), ours.nodes.len(), "{what} {key}");
        for (k, (node, parts)) in ours.values.iter().zip(theirs).enumerate() {
            let (re, im) = node[j];
            let parts = reals(parts);
            let what = format!("{what} {key}[{k}]");
            if ours.complex {
                same_bits(&[re, im], &parts, &what);
            } else {
                same_bits(&[re], &parts, &what);
                assert_eq!(im.to_bits(), 0.0f64.to_bits(), "{what}: imaginary part");
            }
        }
    }
}
