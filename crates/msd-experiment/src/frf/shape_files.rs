//! What a set's shapes are compared with and drawn on, from files: another set of shapes
//! (UFF datasets 55, `reference_shapes`) and the nodes' coordinates (datasets 15 or
//! 2411, `geometry`).

use crate::error::{ExperimentError, Result};
use crate::sources::Sources;
use msd_modal::{Dof, ModeSetFit, ShapeComparison, ShapeEntry, compare_shapes};
use msd_signal::Complex64;
use serde::Serialize;
use std::path::Path;

/// A set's shapes against the shapes of a file.
#[derive(Debug, Clone, Serialize)]
pub struct ReferenceShapes {
    /// The file, as the config gives it (relative to the config file).
    pub file: String,
    /// Each of the file's modes in words (its analysis type, number and frequency).
    pub modes: Vec<String>,
    /// The MAC on the DOFs both give, with the DOFs left out.
    #[serde(flatten)]
    pub comparison: ShapeComparison,
}

/// Reads the shapes of `file` (resolved against `dir`) and compares `fit`'s with them.
/// Errors name the file: unreadable, no dataset 55, or too few DOFs shared.
pub(crate) fn reference_shapes(
    fit: &ModeSetFit,
    file: &Path,
    sources: &Sources,
) -> Result<ReferenceShapes> {
    let path = sources.path(file);
    let key = "frequency_response.reference_shapes";
    let uff = sources.uff(&path)?;
    if uff.data_at_nodes.is_empty() {
        return Err(ExperimentError::data(
            &path,
            format!("{key}: the file holds no data at nodes (dataset 55): expected mode shapes"),
        ));
    }
    let theirs: Vec<Vec<ShapeEntry>> = uff.data_at_nodes.iter().map(entries).collect();
    for (i, shape) in theirs.iter().enumerate() {
        if let Some(e) = shape
            .iter()
            .find(|e| !(e.re.is_finite() && e.im.is_finite()))
        {
            return Err(ExperimentError::data(
                &path,
                format!(
                    "{key}: shape {} (the file's dataset 55 number {}) has {} + {}j at DOF {}: expected finite numbers",
                    i + 1,
                    i + 1,
                    e.re,
                    e.im,
                    e.dof()
                ),
            ));
        }
    }
    let ours: Vec<Vec<ShapeEntry>> = fit.modes.iter().map(|m| m.shape.clone()).collect();
    let comparison = compare_shapes(&ours, &theirs)
        .map_err(|e| ExperimentError::data(&path, format!("{key}: {e}")))?;
    let modes = uff
        .data_at_nodes
        .iter()
        .map(|d| {
            let text = d.to_string();
            text.split(',').next().unwrap_or_default().to_string()
        })
        .collect();
    Ok(ReferenceShapes {
        file: file.display().to_string(),
        modes,
        comparison,
    })
}

/// The shape of a dataset 55 as entries: value d (from 1) at a node is direction d.
fn entries(data: &msd_uff::Data55) -> Vec<ShapeEntry> {
    let mut out = Vec::new();
    for (node, values) in data.nodes.iter().zip(&data.values) {
        let Ok(node) = u32::try_from(*node) else {
            continue;
        };
        for (d, &(re, im)) in values.iter().enumerate() {
            let dof = Dof {
                node,
                direction: d as i32 + 1,
            };
            out.push(ShapeEntry::new(dof, Complex64::new(re, im)));
        }
    }
    out
}

/// The nodes a set's shapes are drawn on: those of `geometry` (resolved against `dir`),
/// else those the set's own UFF file holds (`own`). Errors name the file: unreadable, or
/// no node in it.
pub(crate) fn geometry(
    geometry: Option<&Path>,
    own: Vec<msd_uff::Node>,
    sources: &Sources,
) -> Result<Vec<msd_uff::Node>> {
    let Some(file) = geometry else {
        return Ok(own);
    };
    let path = sources.path(file);
    let uff = sources.uff(&path)?;
    if uff.nodes.is_empty() {
        return Err(ExperimentError::data(
            &path,
            "frequency_response.geometry: the file holds no nodes (datasets 15 or 2411): expected the coordinates of the measured points",
        ));
    }
    Ok(uff.nodes)
}
