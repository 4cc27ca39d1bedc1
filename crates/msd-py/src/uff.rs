//! msd-uff's `read` and `write` with the datasets as dicts keyed as pyuff keys them
//! (58/58b functions, 151 header, 164 units, 15/2411 nodes).

use crate::errors;
use msd_signal::Complex64;
use msd_uff::{
    Abscissa, Analysis55, Axis, ByteOrder, Data55, Encoding, Function58, FunctionType, Header151,
    Node, Ordinate, Precision, UffFile, Units164, WriteOptions,
};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyComplex, PyDict, PyList};

/// The prefixes pyuff gives the four axes of a dataset 58 (records 8–11).
const AXES: [&str; 4] = ["abscissa", "ordinate", "orddenom", "z_axis"];

fn axis_of(f: &Function58, i: usize) -> &Axis {
    [
        &f.abscissa_axis,
        &f.ordinate_axis,
        &f.denominator_axis,
        &f.z_axis,
    ][i]
}

fn function_dict<'py>(py: Python<'py>, f: &Function58) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("type", 58)?;
    match f.encoding {
        Encoding::Ascii => d.set_item("binary", 0)?,
        Encoding::Binary(order) => {
            d.set_item("binary", 1)?;
            d.set_item(
                "byte_ordering",
                if order == ByteOrder::Little { 1 } else { 2 },
            )?;
            d.set_item("fp_format", 2)?;
        }
    }
    for (i, id) in f.ids.iter().enumerate() {
        d.set_item(format!("id{}", i + 1), id)?;
    }
    d.set_item("func_type", f.function_type.code())?;
    d.set_item("func_id", f.function_id)?;
    d.set_item("ver_num", f.version)?;
    d.set_item("load_case_id", f.load_case)?;
    d.set_item("rsp_ent_name", &f.response_entity)?;
    d.set_item("rsp_node", f.response_node)?;
    d.set_item("rsp_dir", f.response_direction)?;
    d.set_item("ref_ent_name", &f.reference_entity)?;
    d.set_item("ref_node", f.reference_node)?;
    d.set_item("ref_dir", f.reference_direction)?;
    let complex = matches!(f.ordinate, Ordinate::Complex(_));
    let ord_data_type = match (f.precision, complex) {
        (Precision::Single, false) => 2,
        (Precision::Double, false) => 4,
        (Precision::Single, true) => 5,
        (Precision::Double, true) => 6,
    };
    d.set_item("ord_data_type", ord_data_type)?;
    d.set_item("num_pts", f.len())?;
    let x = f.abscissa_values();
    match &f.abscissa {
        Abscissa::Even { start, step } => {
            d.set_item("abscissa_spacing", 1)?;
            d.set_item("abscissa_min", *start)?;
            d.set_item("abscissa_inc", *step)?;
        }
        Abscissa::Uneven(_) => {
            d.set_item("abscissa_spacing", 0)?;
            d.set_item("abscissa_min", x.first().copied().unwrap_or(0.0))?;
            d.set_item("abscissa_inc", 0.0)?;
        }
    }
    d.set_item("z_axis_value", f.z_axis_value)?;
    for (i, prefix) in AXES.iter().enumerate() {
        let a = axis_of(f, i);
        d.set_item(format!("{prefix}_spec_data_type"), a.data_type)?;
        d.set_item(format!("{prefix}_len_unit_exp"), a.length_exponent)?;
        d.set_item(format!("{prefix}_force_unit_exp"), a.force_exponent)?;
        d.set_item(format!("{prefix}_temp_unit_exp"), a.temperature_exponent)?;
        d.set_item(format!("{prefix}_axis_lab"), &a.label)?;
        d.set_item(format!("{prefix}_axis_units_lab"), &a.units)?;
    }
    d.set_item("x", PyArray1::from_vec(py, x))?;
    match &f.ordinate {
        Ordinate::Real(v) => d.set_item("data", PyArray1::from_slice(py, v))?,
        Ordinate::Complex(v) => {
            let c: Vec<Complex64> = v.iter().map(|(re, im)| Complex64::new(*re, *im)).collect();
            d.set_item("data", PyArray1::from_vec(py, c))?
        }
    }
    Ok(d)
}

fn header_dict<'py>(py: Python<'py>, h: &Header151) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("type", 151)?;
    d.set_item("model_name", &h.model_name)?;
    d.set_item("description", &h.description)?;
    d.set_item("db_app", &h.db_program)?;
    d.set_item("date_db_created", &h.db_created_date)?;
    d.set_item("time_db_created", &h.db_created_time)?;
    d.set_item("version_db1", h.db_version1)?;
    d.set_item("version_db2", h.db_version2)?;
    d.set_item("file_type", h.file_type)?;
    d.set_item("date_db_saved", &h.db_saved_date)?;
    d.set_item("time_db_saved", &h.db_saved_time)?;
    d.set_item("program", &h.program)?;
    d.set_item("date_file_written", &h.written_date)?;
    d.set_item("time_file_written", &h.written_time)?;
    Ok(d)
}

fn units_dict<'py>(py: Python<'py>, u: &Units164) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("type", 164)?;
    d.set_item("units_code", u.code)?;
    d.set_item("units_description", &u.description)?;
    d.set_item("temp_mode", u.temperature_mode)?;
    d.set_item("length", u.length)?;
    d.set_item("force", u.force)?;
    d.set_item("temp", u.temperature)?;
    d.set_item("temp_offset", u.temperature_offset)?;
    Ok(d)
}

/// The nodes of one dataset (15 or 2411) as pyuff's one dict with arrays.
fn nodes_dict<'py>(py: Python<'py>, nodes: &[&Node], kind: i32) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("type", kind)?;
    let col = |f: fn(&Node) -> f64| PyArray1::from_vec(py, nodes.iter().map(|n| f(n)).collect());
    d.set_item("node_nums", col(|n| n.label as f64))?;
    d.set_item("def_cs", col(|n| n.definition_cs as f64))?;
    d.set_item("disp_cs", col(|n| n.displacement_cs as f64))?;
    d.set_item("color", col(|n| n.color as f64))?;
    d.set_item("x", col(|n| n.x))?;
    d.set_item("y", col(|n| n.y))?;
    d.set_item("z", col(|n| n.z))?;
    Ok(d)
}

/// Data at nodes (55) as pyuff's dict: the analysis's fields by its type, `r1`…`rN`.
fn data55_dict<'py>(py: Python<'py>, d: &Data55) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("type", 55)?;
    for (i, id) in d.ids.iter().enumerate() {
        out.set_item(format!("id{}", i + 1), id)?;
    }
    out.set_item("model_type", d.model_type)?;
    out.set_item("analysis_type", d.analysis.code())?;
    out.set_item("data_ch", d.data_characteristic)?;
    out.set_item("spec_data_type", d.specific_data_type)?;
    out.set_item("data_type", if d.complex { 5 } else { 2 })?;
    out.set_item("n_data_per_node", d.values_per_node)?;
    let c = |(re, im): (f64, f64)| Complex64::new(re, im);
    match &d.analysis {
        Analysis55::NormalMode {
            load_case,
            mode,
            frequency,
            modal_mass,
            viscous_damping,
            hysteretic_damping,
        } => {
            out.set_item("load_case", load_case)?;
            out.set_item("mode_n", mode)?;
            out.set_item("freq", frequency)?;
            out.set_item("modal_m", modal_mass)?;
            out.set_item("modal_damp_vis", viscous_damping)?;
            out.set_item("modal_damp_his", hysteretic_damping)?;
        }
        Analysis55::ComplexEigenvalue {
            load_case,
            mode,
            eigenvalue,
            modal_a,
            modal_b,
            ..
        } => {
            out.set_item("load_case", load_case)?;
            out.set_item("mode_n", mode)?;
            let z = |(re, im): (f64, f64)| PyComplex::from_doubles(py, re, im);
            out.set_item("eig", z(*eigenvalue))?;
            out.set_item("modal_a", z(*modal_a))?;
            out.set_item("modal_b", z(*modal_b))?;
        }
        Analysis55::FrequencyResponse {
            load_case,
            frequency_step,
            frequency,
        } => {
            out.set_item("load_case", load_case)?;
            out.set_item("freq_step_n", frequency_step)?;
            out.set_item("freq", frequency)?;
        }
        other => {
            out.set_item("integers", other.integers())?;
            out.set_item("reals", other.reals())?;
        }
    }
    out.set_item("node_nums", PyArray1::from_slice(py, &d.nodes))?;
    for k in 0..d.values_per_node {
        let column = d
            .values
            .iter()
            .map(|row| row.get(k).copied().unwrap_or((f64::NAN, 0.0)));
        if d.complex {
            out.set_item(
                format!("r{}", k + 1),
                PyArray1::from_vec(py, column.map(c).collect()),
            )?;
        } else {
            out.set_item(
                format!("r{}", k + 1),
                PyArray1::from_vec(py, column.map(|v| v.0).collect()),
            )?;
        }
    }
    Ok(out)
}

/// uff_read(path)
/// --
///
/// msd-uff's `read`: (datasets as pyuff-keyed dicts, skipped datasets as dicts).
#[pyfunction]
pub fn uff_read<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<(Bound<'py, PyList>, Bound<'py, PyList>)> {
    let file = py.detach(|| msd_uff::read(&path)).map_err(uff_error)?;
    let out = PyList::empty(py);
    if let Some(h) = &file.header {
        out.append(header_dict(py, h)?)?;
    }
    if let Some(u) = &file.units {
        out.append(units_dict(py, u)?)?;
    }
    for (precision, kind) in [(Precision::Single, 15), (Precision::Double, 2411)] {
        let nodes: Vec<&Node> = file
            .nodes
            .iter()
            .filter(|n| n.precision == precision)
            .collect();
        if !nodes.is_empty() {
            out.append(nodes_dict(py, &nodes, kind)?)?;
        }
    }
    for d in &file.data_at_nodes {
        out.append(data55_dict(py, d)?)?;
    }
    for f in &file.functions {
        out.append(function_dict(py, f)?)?;
    }
    let skipped = PyList::empty(py);
    for s in &file.skipped {
        let d = PyDict::new(py);
        d.set_item("type", s.number)?;
        d.set_item("offset", s.offset)?;
        d.set_item("line", s.line)?;
        d.set_item("binary", s.binary)?;
        d.set_item("note", &s.note)?;
        skipped.append(d)?;
    }
    Ok((out, skipped))
}

fn uff_error(e: msd_uff::UffError) -> PyErr {
    match &e {
        msd_uff::UffError::Io { source, .. } => {
            let message = e.to_string();
            match source.kind() {
                std::io::ErrorKind::NotFound => {
                    pyo3::exceptions::PyFileNotFoundError::new_err(message)
                }
                _ => pyo3::exceptions::PyOSError::new_err(message),
            }
        }
        _ => errors::value(e),
    }
}

/// A dataset dict's optional field.
fn get<'py, T: FromPyObjectOwned<'py>>(d: &Bound<'py, PyDict>, key: &str) -> PyResult<Option<T>> {
    match d.get_item(key)? {
        None => Ok(None),
        Some(v) if v.is_none() => Ok(None),
        Some(v) => v.extract::<T>().map(Some).map_err(|e| {
            let e: PyErr = e.into();
            let shown = v.repr().map(|r| r.to_string()).unwrap_or_default();
            let shown: String = shown.chars().take(60).collect();
            PyValueError::new_err(format!("field '{key}' = {shown}: {}", e.value(d.py())))
        }),
    }
}

fn required<'py, T: FromPyObjectOwned<'py>>(
    d: &Bound<'py, PyDict>,
    key: &str,
    kind: i64,
) -> PyResult<T> {
    get(d, key)?.ok_or_else(|| {
        PyValueError::new_err(format!("missing field '{key}': dataset {kind} needs it"))
    })
}

fn function_from<'py>(d: &Bound<'py, PyDict>) -> PyResult<Function58> {
    let complex: bool = required(d, "_complex", 58)?;
    let ordinate = if complex {
        let data: PyReadonlyArray1<'py, Complex64> = required(d, "data", 58)?;
        Ordinate::Complex(data.as_array().iter().map(|c| (c.re, c.im)).collect())
    } else {
        let data: PyReadonlyArray1<'py, f64> = required(d, "data", 58)?;
        Ordinate::Real(data.as_array().to_vec())
    };
    let spacing: i64 = required(d, "abscissa_spacing", 58)?;
    let abscissa = if spacing == 1 {
        Abscissa::Even {
            start: required(d, "abscissa_min", 58)?,
            step: required(d, "abscissa_inc", 58)?,
        }
    } else {
        let x: PyReadonlyArray1<'py, f64> = required(d, "x", 58)?;
        Abscissa::Uneven(x.as_array().to_vec())
    };
    let func_type: i32 = get(d, "func_type")?.unwrap_or(0);
    let mut f = Function58::new(FunctionType::from_code(func_type), abscissa, ordinate);
    for i in 0..5 {
        if let Some(id) = get::<String>(d, &format!("id{}", i + 1))? {
            f.ids[i] = id;
        }
    }
    macro_rules! field {
        ($key:literal, $target:expr) => {
            if let Some(v) = get(d, $key)? {
                $target = v;
            }
        };
    }
    field!("func_id", f.function_id);
    field!("ver_num", f.version);
    field!("load_case_id", f.load_case);
    field!("rsp_ent_name", f.response_entity);
    field!("rsp_node", f.response_node);
    field!("rsp_dir", f.response_direction);
    field!("ref_ent_name", f.reference_entity);
    field!("ref_node", f.reference_node);
    field!("ref_dir", f.reference_direction);
    field!("z_axis_value", f.z_axis_value);
    let ord_data_type: i64 = get(d, "ord_data_type")?.unwrap_or(if complex { 6 } else { 4 });
    f.precision = match ord_data_type {
        2 | 5 => Precision::Single,
        4 | 6 => Precision::Double,
        other => {
            return Err(PyValueError::new_err(format!(
                "dataset field 'ord_data_type' = {other}: expected 2 or 4 (real), 5 or 6 (complex)"
            )));
        }
    };
    if matches!(ord_data_type, 2 | 4) == complex {
        return Err(PyValueError::new_err(format!(
            "dataset field 'ord_data_type' = {ord_data_type} does not match the {} data",
            if complex { "complex" } else { "real" }
        )));
    }
    let binary: i64 = get(d, "binary")?.unwrap_or(0);
    f.encoding = if binary != 0 {
        let order: i64 = get(d, "byte_ordering")?.unwrap_or(1);
        Encoding::Binary(if order == 2 {
            ByteOrder::Big
        } else {
            ByteOrder::Little
        })
    } else {
        Encoding::Ascii
    };
    let mut axes = [
        f.abscissa_axis.clone(),
        f.ordinate_axis.clone(),
        f.denominator_axis.clone(),
        f.z_axis.clone(),
    ];
    for (prefix, axis) in AXES.iter().zip(axes.iter_mut()) {
        if let Some(v) = get(d, &format!("{prefix}_spec_data_type"))? {
            axis.data_type = v;
        }
        if let Some(v) = get(d, &format!("{prefix}_len_unit_exp"))? {
            axis.length_exponent = v;
        }
        if let Some(v) = get(d, &format!("{prefix}_force_unit_exp"))? {
            axis.force_exponent = v;
        }
        if let Some(v) = get(d, &format!("{prefix}_temp_unit_exp"))? {
            axis.temperature_exponent = v;
        }
        if let Some(v) = get(d, &format!("{prefix}_axis_lab"))? {
            axis.label = v;
        }
        if let Some(v) = get(d, &format!("{prefix}_axis_units_lab"))? {
            axis.units = v;
        }
    }
    let [a, o, den, z] = axes;
    (
        f.abscissa_axis,
        f.ordinate_axis,
        f.denominator_axis,
        f.z_axis,
    ) = (a, o, den, z);
    Ok(f)
}

fn header_from(d: &Bound<'_, PyDict>) -> PyResult<Header151> {
    let mut h = Header151::default();
    macro_rules! field {
        ($key:literal, $target:expr) => {
            if let Some(v) = get(d, $key)? {
                $target = v;
            }
        };
    }
    field!("model_name", h.model_name);
    field!("description", h.description);
    field!("db_app", h.db_program);
    field!("date_db_created", h.db_created_date);
    field!("time_db_created", h.db_created_time);
    field!("version_db1", h.db_version1);
    field!("version_db2", h.db_version2);
    field!("file_type", h.file_type);
    field!("date_db_saved", h.db_saved_date);
    field!("time_db_saved", h.db_saved_time);
    field!("program", h.program);
    field!("date_file_written", h.written_date);
    field!("time_file_written", h.written_time);
    Ok(h)
}

fn units_from(d: &Bound<'_, PyDict>) -> PyResult<Units164> {
    let mut u = Units164::default();
    macro_rules! field {
        ($key:literal, $target:expr) => {
            if let Some(v) = get(d, $key)? {
                $target = v;
            }
        };
    }
    field!("units_code", u.code);
    field!("units_description", u.description);
    field!("temp_mode", u.temperature_mode);
    field!("length", u.length);
    field!("force", u.force);
    field!("temp", u.temperature);
    field!("temp_offset", u.temperature_offset);
    Ok(u)
}

fn nodes_from<'py>(d: &Bound<'py, PyDict>, kind: i64, out: &mut Vec<Node>) -> PyResult<()> {
    let column = |key: &str| -> PyResult<Option<Vec<f64>>> {
        Ok(get::<PyReadonlyArray1<'py, f64>>(d, key)?.map(|a| a.as_array().to_vec()))
    };
    let labels = column("node_nums")?.ok_or_else(|| {
        PyValueError::new_err(format!(
            "missing field 'node_nums': dataset {kind} needs it"
        ))
    })?;
    let n = labels.len();
    let or_zeros = |c: Option<Vec<f64>>, key: &str| -> PyResult<Vec<f64>> {
        let c = c.unwrap_or_else(|| vec![0.0; n]);
        if c.len() != n {
            return Err(PyValueError::new_err(format!(
                "dataset {kind} field '{key}' has {} values for {n} nodes",
                c.len()
            )));
        }
        Ok(c)
    };
    let def_cs = or_zeros(column("def_cs")?, "def_cs")?;
    let disp_cs = or_zeros(column("disp_cs")?, "disp_cs")?;
    let color = or_zeros(column("color")?, "color")?;
    let x = or_zeros(column("x")?, "x")?;
    let y = or_zeros(column("y")?, "y")?;
    let z = or_zeros(column("z")?, "z")?;
    let precision = if kind == 15 {
        Precision::Single
    } else {
        Precision::Double
    };
    for i in 0..n {
        let int = |v: f64, key: &str| -> PyResult<i64> {
            if v.fract() == 0.0 && v.abs() < 1e15 {
                Ok(v as i64)
            } else {
                Err(PyValueError::new_err(format!(
                    "dataset {kind} field '{key}' value {v} is not an integer"
                )))
            }
        };
        out.push(Node {
            label: int(labels[i], "node_nums")?,
            definition_cs: int(def_cs[i], "def_cs")? as i32,
            displacement_cs: int(disp_cs[i], "disp_cs")? as i32,
            color: int(color[i], "color")? as i32,
            x: x[i],
            y: y[i],
            z: z[i],
            precision,
        });
    }
    Ok(())
}

/// Data at nodes (55) from pyuff's dict (`_complex` set by the Python layer).
fn data55_from<'py>(d: &Bound<'py, PyDict>) -> PyResult<Data55> {
    let mut out = Data55::default();
    for i in 0..5 {
        if let Some(id) = get::<String>(d, &format!("id{}", i + 1))? {
            out.ids[i] = id;
        }
    }
    if let Some(v) = get(d, "model_type")? {
        out.model_type = v;
    }
    if let Some(v) = get(d, "data_ch")? {
        out.data_characteristic = v;
    }
    if let Some(v) = get(d, "spec_data_type")? {
        out.specific_data_type = v;
    }
    let analysis_type: i32 = get(d, "analysis_type")?.unwrap_or(2);
    let int = |key: &str| -> PyResult<i64> { Ok(get(d, key)?.unwrap_or(0)) };
    let real = |key: &str| -> PyResult<f64> { Ok(get(d, key)?.unwrap_or(0.0)) };
    let complex = |key: &str| -> PyResult<(f64, f64)> {
        match d.get_item(key)? {
            None => Ok((0.0, 0.0)),
            Some(v) if v.is_none() => Ok((0.0, 0.0)),
            Some(v) => match v.cast::<PyComplex>() {
                Ok(c) => Ok((c.real(), c.imag())),
                Err(_) => Ok((real(key)?, 0.0)),
            },
        }
    };
    let (integers, reals) = match analysis_type {
        2 => (
            vec![int("load_case")?, int("mode_n")?],
            vec![
                real("freq")?,
                real("modal_m")?,
                real("modal_damp_vis")?,
                real("modal_damp_his")?,
            ],
        ),
        3 | 7 => {
            let (e, a, b) = (complex("eig")?, complex("modal_a")?, complex("modal_b")?);
            (
                vec![int("load_case")?, int("mode_n")?],
                vec![e.0, e.1, a.0, a.1, b.0, b.1],
            )
        }
        5 => (
            vec![int("load_case")?, int("freq_step_n")?],
            vec![real("freq")?],
        ),
        _ => (
            get(d, "integers")?.unwrap_or_default(),
            get(d, "reals")?.unwrap_or_default(),
        ),
    };
    out.analysis = Analysis55::from_parameters(analysis_type, integers, reals);
    let nodes: Vec<i64> = required(d, "node_nums", 55)?;
    let is_complex: bool = required(d, "_complex", 55)?;
    let per_node: usize = get(d, "n_data_per_node")?.unwrap_or(3);
    let mut columns: Vec<Vec<(f64, f64)>> = Vec::with_capacity(per_node);
    for k in 1..=per_node {
        let key = format!("r{k}");
        let column: Vec<(f64, f64)> = if is_complex {
            let a: PyReadonlyArray1<'py, Complex64> = required(d, &key, 55)?;
            a.as_array().iter().map(|c| (c.re, c.im)).collect()
        } else {
            let a: PyReadonlyArray1<'py, f64> = required(d, &key, 55)?;
            a.as_array().iter().map(|v| (*v, 0.0)).collect()
        };
        if column.len() != nodes.len() {
            return Err(PyValueError::new_err(format!(
                "dataset 55 field '{key}' has {} values for {} nodes",
                column.len(),
                nodes.len()
            )));
        }
        columns.push(column);
    }
    out.complex = is_complex;
    out.values_per_node = per_node;
    out.values = (0..nodes.len())
        .map(|i| columns.iter().map(|c| c[i]).collect())
        .collect();
    out.nodes = nodes;
    Ok(out)
}

/// One dataset dict into `file`, by its type.
fn add_dataset(file: &mut UffFile, d: &Bound<'_, PyDict>) -> PyResult<()> {
    let kind: i64 = get(d, "type")?.ok_or_else(|| {
        PyValueError::new_err("missing field 'type': expected 58, 55, 151, 164, 15 or 2411")
    })?;
    match kind {
        58 => file.functions.push(function_from(d)?),
        151 => file.header = Some(header_from(d)?),
        164 => file.units = Some(units_from(d)?),
        15 | 2411 => nodes_from(d, kind, &mut file.nodes)?,
        55 => file.data_at_nodes.push(data55_from(d)?),
        other => {
            return Err(PyValueError::new_err(format!(
                "type {other}: msd.uff writes 58 (and 58b), 55, 151, 164, 15 and 2411"
            )));
        }
    }
    Ok(())
}

/// uff_write(path, datasets, exact)
/// --
///
/// msd-uff's `write` of pyuff-keyed dataset dicts (58 with '_complex' set by the Python
/// layer, 151, 164, 15, 2411).
#[pyfunction]
pub fn uff_write<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    datasets: Vec<Bound<'py, PyDict>>,
    exact: bool,
) -> PyResult<()> {
    let mut file = UffFile::default();
    for (i, d) in datasets.iter().enumerate() {
        add_dataset(&mut file, d).map_err(|e| errors::within(py, &format!("datasets[{i}]"), e))?;
    }
    let options = WriteOptions {
        ascii: if exact {
            msd_uff::AsciiNumbers::Exact
        } else {
            msd_uff::AsciiNumbers::Fixed
        },
    };
    py.detach(|| msd_uff::write(&path, &file, &options))
        .map_err(uff_error)
}
