//! A vector or a matrix as channels.

/// The channels of a `rows × cols` array whose element (r, c) is `at(r, c)`: a vector
/// (one row or one column) is one channel named `name`; a matrix is split along its
/// shorter dimension (columns when square), channel j named `name[j]`.
///
/// Samples run along the longer dimension: a record has far more samples than channels,
/// whichever way the program that wrote it laid them out.
pub(crate) fn channels(
    name: &str,
    rows: usize,
    cols: usize,
    at: impl Fn(usize, usize) -> f64,
) -> Vec<(String, Vec<f64>)> {
    if rows == 1 || cols == 1 {
        let n = rows.max(cols);
        let values = (0..n)
            .map(|i| if rows == 1 { at(0, i) } else { at(i, 0) })
            .collect();
        return vec![(name.to_string(), values)];
    }
    if cols <= rows {
        (0..cols)
            .map(|c| {
                (
                    format!("{name}[{c}]"),
                    (0..rows).map(|r| at(r, c)).collect(),
                )
            })
            .collect()
    } else {
        (0..rows)
            .map(|r| {
                (
                    format!("{name}[{r}]"),
                    (0..cols).map(|c| at(r, c)).collect(),
                )
            })
            .collect()
    }
}

/// The dimensions of `shape` as rows × columns, when it has at most two that are not 1.
pub(crate) fn as_matrix(shape: &[usize]) -> Option<(usize, usize)> {
    let big: Vec<usize> = shape.iter().copied().filter(|&d| d != 1).collect();
    match big[..] {
        [] => Some((1, 1)),
        [n] => Some((n, 1)),
        [r, c] => Some((r, c)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_run_along_the_longer_dimension() {
        let m = |r: usize, c: usize| (10 * r + c) as f64;
        assert_eq!(
            channels("x", 1, 3, m),
            vec![("x".into(), vec![0.0, 1.0, 2.0])]
        );
        assert_eq!(
            channels("x", 3, 1, m),
            vec![("x".into(), vec![0.0, 10.0, 20.0])]
        );
        let tall = channels("y", 3, 2, m);
        assert_eq!(tall[1], ("y[1]".into(), vec![1.0, 11.0, 21.0]));
        let wide = channels("y", 2, 3, m);
        assert_eq!(wide[1], ("y[1]".into(), vec![10.0, 11.0, 12.0]));
        assert_eq!(as_matrix(&[1, 5, 1]), Some((5, 1)));
        assert_eq!(as_matrix(&[2, 5, 3]), None);
    }
}
