//! pyOMA's setup files: `channel_dofs.txt` (a header, then per channel: number, node,
//! azimuth and elevation in degrees, name; tab- or space-separated) and `setup_info.txt`
//! (labelled lines, each followed by its values: the sampling rate, the reference,
//! deleted, acceleration, velocity and displacement channels).

use msd_modal::Quantity;

/// One line of `channel_dofs.txt`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ChannelDof {
    pub channel: usize,
    pub node: u32,
    pub azimuth_deg: f64,
    pub elevation_deg: f64,
    pub name: String,
}

/// What `setup_info.txt` says.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct SetupInfo {
    pub sample_rate_hz: f64,
    pub references: Vec<usize>,
    pub deleted: Vec<usize>,
    pub accelerations: Vec<usize>,
    pub velocities: Vec<usize>,
    pub displacements: Vec<usize>,
}

impl SetupInfo {
    /// The quantity of `channel` (acceleration where the file does not say).
    pub(crate) fn quantity(&self, channel: usize) -> Quantity {
        if self.velocities.contains(&channel) {
            Quantity::Velocity
        } else if self.displacements.contains(&channel) {
            Quantity::Displacement
        } else {
            Quantity::Acceleration
        }
    }
}

/// The channels of `channel_dofs.txt`; the error names the line.
pub(crate) fn channel_dofs(text: &str) -> Result<Vec<ChannelDof>, String> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate().skip(1) {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        let bad = |what: &str| {
            format!(
                "line {}: {what} in {line:?}: expected channel, node, azimuth, elevation[, name]",
                n + 1
            )
        };
        let [channel, node, az, el, rest @ ..] = &fields[..] else {
            return Err(bad("too few fields"));
        };
        out.push(ChannelDof {
            channel: channel
                .parse()
                .map_err(|_| bad("a channel that is not a whole number"))?,
            node: node
                .parse()
                .map_err(|_| bad("a node that is not a whole number"))?,
            azimuth_deg: az
                .parse()
                .map_err(|_| bad("an azimuth that is not a number"))?,
            elevation_deg: el
                .parse()
                .map_err(|_| bad("an elevation that is not a number"))?,
            name: rest
                .first()
                .map_or_else(|| format!("channel {channel}"), |s| (*s).to_string()),
        });
    }
    if out.is_empty() {
        return Err("no channels: expected a header line, then one line per channel".into());
    }
    Ok(out)
}

/// The settings of `setup_info.txt`; the error names the label.
pub(crate) fn setup_info(text: &str) -> Result<SetupInfo, String> {
    let lines: Vec<&str> = text.lines().map(str::trim).collect();
    let after = |label: &str| -> Option<&str> {
        let at = lines.iter().position(|l| {
            l.to_ascii_lowercase()
                .starts_with(&label.to_ascii_lowercase())
        })?;
        Some(
            lines
                .get(at + 1)
                .copied()
                .filter(|l| !l.ends_with(':'))
                .unwrap_or(""),
        )
    };
    let list = |label: &str| -> Result<Vec<usize>, String> {
        after(label).map_or(Ok(Vec::new()), |values| {
            values
                .split_whitespace()
                .map(|v| {
                    v.parse().map_err(|_| {
                        format!("{label} {values:?}: expected channel numbers separated by blanks")
                    })
                })
                .collect()
        })
    };
    let rate = after("Sampling Rate").ok_or("no \"Sampling Rate [Hz]:\" line")?;
    Ok(SetupInfo {
        sample_rate_hz: rate
            .parse()
            .map_err(|_| format!("Sampling Rate {rate:?}: expected a number"))?,
        references: list("Reference Channels")?,
        deleted: list("Delete Channels")?,
        accelerations: list("Accel. Channels")?,
        velocities: list("Velo. Channels")?,
        displacements: list("Disp. Channels")?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_steel_frames_files_read_as_pyoma_writes_them() {
        let dofs = "Channel-Nr.\tNode\tAzimuth\tElevation\tChannel Name\n0\t5\t28.86\t-8.69\tvib_l\n3\t24\t0.0\t180.0\tref_x\n";
        let d = channel_dofs(dofs).expect("reads");
        assert_eq!(
            (
                d[1].channel,
                d[1].node,
                d[1].elevation_deg,
                d[1].name.as_str()
            ),
            (3, 24, 180.0, "ref_x")
        );
        let info = "Setup Name:\nmeasurement_1\nSampling Rate [Hz]:\n256\nReference Channels:\n3 4\nDelete Channels:\n5\nAccel. Channels:\n3 4 5\nVelo. Channels:\n0 1 2\nDisp. Channels:\n";
        let s = setup_info(info).expect("reads");
        assert_eq!(
            (s.sample_rate_hz, s.references.clone(), s.deleted.clone()),
            (256.0, vec![3, 4], vec![5])
        );
        assert_eq!(
            (s.quantity(1), s.quantity(3)),
            (Quantity::Velocity, Quantity::Acceleration)
        );
        assert!(s.displacements.is_empty());
        let err = channel_dofs("h\n0\t5\tx\t1\n").unwrap_err();
        assert!(err.starts_with("line 2: an azimuth"), "{err}");
    }
}
