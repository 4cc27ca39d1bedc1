//! Prints one JSON object per dataset of a UFF file.
//!
//! ```sh
//! cargo run -p msd-uff --example dump -- crates/msd-uff/fixtures/pyuff/mixed.uff
//! ```
//!
//! Functions (58, 58b) give `type`, `binary`, `func_type`, `rsp_node`, `rsp_dir`, `ref_node`,
//! `ref_dir`, `abscissa_min`, `abscissa_inc` (null if uneven), `num_pts`, `complex`, `first`
//! and `last` (`[re, im]` of the first and last ordinate) and a few more; the header (151)
//! and units (164) their fields; each run of nodes (15, 2411) its nodes; data at nodes (55)
//! all its fields and `analysis_type`; skipped datasets their number and byte offset.

use msd_uff::{Abscissa, Encoding, Function58, Ordinate, Precision, UffFile};
use serde_json::{Value, json};

fn function(index: usize, f: &Function58, file: &UffFile) -> Value {
    let point = |k: Option<usize>| match (&f.ordinate, k) {
        (Ordinate::Real(y), Some(k)) => json!([y[k], 0.0]),
        (Ordinate::Complex(y), Some(k)) => json!([y[k].0, y[k].1]),
        (_, None) => Value::Null,
    };
    let x = f.abscissa_values();
    let (min, inc) = match f.abscissa {
        Abscissa::Even { start, step } => (json!(start), json!(step)),
        Abscissa::Uneven(_) => (json!(x.first()), Value::Null),
    };
    let trailing: usize = file
        .trailing
        .iter()
        .filter(|t| t.function == index)
        .map(|t| t.len)
        .sum();
    json!({
        "type": 58,
        "binary": f.encoding != Encoding::Ascii,
        "func_type": f.function_type.code(),
        "func_name": f.function_type.to_string(),
        "rsp_node": f.response_node,
        "rsp_dir": f.response_direction,
        "ref_node": f.reference_node,
        "ref_dir": f.reference_direction,
        "abscissa_min": min,
        "abscissa_inc": inc,
        "abscissa_max": x.last(),
        "num_pts": f.len(),
        "complex": matches!(f.ordinate, Ordinate::Complex(_)),
        "double": f.precision == Precision::Double,
        "first": point((!f.is_empty()).then_some(0)),
        "last": point(f.len().checked_sub(1)),
        "id1": f.ids[0],
        "abscissa_units": f.abscissa_axis.units,
        "ordinate_units": f.ordinate_axis.units,
        "trailing_bytes": trailing,
    })
}

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: cargo run -p msd-uff --example dump -- FILE");
        std::process::exit(2);
    };
    let file = match msd_uff::read(&path) {
        Ok(file) => file,
        Err(err) => {
            eprintln!("{err}");
            std::process::exit(1);
        }
    };
    let mut out = Vec::new();
    if let Some(h) = &file.header {
        let mut v = serde_json::to_value(h).unwrap_or(Value::Null);
        v["type"] = json!(151);
        out.push(v);
    }
    if let Some(u) = &file.units {
        let mut v = serde_json::to_value(u).unwrap_or(Value::Null);
        v["type"] = json!(164);
        out.push(v);
    }
    for run in file.nodes.chunk_by(|a, b| a.precision == b.precision) {
        let double = run.first().map(|n| n.precision) == Some(Precision::Double);
        out.push(json!({"type": if double { 2411 } else { 15 }, "nodes": run}));
    }
    out.extend(file.data_at_nodes.iter().map(|d| {
        let mut v = serde_json::to_value(d).unwrap_or(Value::Null);
        v["type"] = json!(55);
        v["analysis_type"] = json!(d.analysis.code());
        v
    }));
    out.extend(
        file.functions
            .iter()
            .enumerate()
            .map(|(i, f)| function(i, f, &file)),
    );
    out.extend(file.skipped.iter().map(|s| {
        json!({"type": s.number, "binary": s.binary, "skipped": true, "offset": s.offset,
            "line": s.line, "note": s.note})
    }));
    for v in out {
        println!("{v}");
    }
}
