//! A test machine's recording: the imposed stroke as its input, the measured force as
//! its channel.

use crate::error::{IdentError, Result};
use msd_signal::{Channel, Quantity, Recording};

/// A test machine's recording named `name` on the grid `i·dt`: the imposed stroke x (m)
/// as its measured input and the force F (N) the machine applies to the specimen as its
/// one channel.
///
/// ```
/// use msd_ident::dynamometer::{machine_recording, stroke_and_force};
/// let r = machine_recording("2 Hz", 1e-3, vec![0.0, 1e-3], vec![0.0, 5.0]);
/// assert_eq!((r.inputs[0].name.as_str(), r.channels[0].unit.as_str()), ("stroke", "N"));
/// assert_eq!(stroke_and_force(&r)?.1, &[0.0, 5.0]);
/// # Ok::<(), msd_ident::IdentError>(())
/// ```
pub fn machine_recording(
    name: impl Into<String>,
    dt: f64,
    stroke: Vec<f64>,
    force: Vec<f64>,
) -> Recording {
    Recording::new(name, 0.0, dt)
        .with_input(Channel::new("stroke", Quantity::Displacement, stroke))
        .with_channel(Channel::new("force", Quantity::Force, force))
}

/// The stroke and the force of a machine recording: its first input, a displacement,
/// and its first channel, a force. Any other shape is refused, naming the recording and
/// the channel that is not what a test machine records.
///
/// ```
/// use msd_ident::dynamometer::{machine_recording, stroke_and_force};
/// use msd_signal::Quantity;
/// let mut r = machine_recording("run", 1e-3, vec![0.0, 1e-3], vec![0.0, 5.0]);
/// r.channels[0].quantity = Quantity::Acceleration;
/// assert_eq!(stroke_and_force(&r).unwrap_err().to_string(),
///     "record `run`, channel `force`: it measures acceleration: a test machine's \
///      recording has the stroke (displacement) as its input and the force as its channel");
/// ```
pub fn stroke_and_force(r: &Recording) -> Result<(&[f64], &[f64])> {
    let wrong = |channel: Option<&Channel>, quantity: Quantity| match channel {
        Some(c) if c.quantity == quantity => None,
        Some(c) => Some((Some(c.name.clone()), format!("it measures {}", c.quantity))),
        None => Some((None, format!("no {quantity} channel"))),
    };
    let fault = wrong(r.inputs.first(), Quantity::Displacement)
        .or_else(|| wrong(r.channels.first(), Quantity::Force));
    if let Some((channel, found)) = fault {
        return Err(IdentError::InvalidRecord {
            record: r.name.clone(),
            channel,
            reason: format!(
                "{found}: a test machine's recording has the stroke (displacement) as its \
                 input and the force as its channel"
            ),
        });
    }
    Ok((&r.inputs[0].samples, &r.channels[0].samples))
}
