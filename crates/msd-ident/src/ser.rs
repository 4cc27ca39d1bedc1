//! serde helpers for the result types: a matrix as its rows, a duration in seconds.

use nalgebra::DMatrix;
use serde::Serializer;
use serde::ser::SerializeSeq;
use std::time::Duration;

/// `serialize_with` for a matrix: its rows, each a list of numbers (`[[a, b], [c, d]]`).
pub(crate) fn matrix_rows<S: Serializer>(m: &DMatrix<f64>, s: S) -> Result<S::Ok, S::Error> {
    let mut rows = s.serialize_seq(Some(m.nrows()))?;
    for row in m.row_iter() {
        let values: Vec<f64> = row.iter().copied().collect();
        rows.serialize_element(&values)?;
    }
    rows.end()
}

/// `serialize_with` for a duration: seconds as a number.
pub(crate) fn seconds<S: Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_matrix_is_its_rows_and_a_duration_its_seconds() -> Result<(), serde_json::Error> {
        let m = DMatrix::from_row_slice(2, 3, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let rows = matrix_rows(&m, serde_json::value::Serializer)?;
        assert_eq!(rows, serde_json::json!([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]));
        let empty = matrix_rows(&DMatrix::zeros(0, 0), serde_json::value::Serializer)?;
        assert_eq!(empty, serde_json::json!([]));
        let t = seconds(&Duration::from_millis(1500), serde_json::value::Serializer)?;
        assert_eq!(t, serde_json::json!(1.5));
        Ok(())
    }
}
