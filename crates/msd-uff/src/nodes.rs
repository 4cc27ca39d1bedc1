//! Geometry and data at nodes: [`Node`] (datasets 15 and 2411), [`Data55`] and its
//! [`Analysis55`] (dataset 55).

use serde::Serialize;

use crate::types::Precision;

/// A node of the geometry: dataset 15 (*Nodes*, coordinates in `E13.5`) or 2411 (*Nodes –
/// Double Precision*, coordinates in `D25.16`).
///
/// Both hold, per node, a label, two coordinate system numbers, a colour and the three
/// coordinates; [`Node::precision`] says which of the two the node was read from, and is
/// written as.
///
/// ```
/// use msd_uff::{Node, Precision};
///
/// let tip = Node { label: 4, x: 1.0, z: -0.25, ..Default::default() };
/// assert_eq!(tip.precision, Precision::Double); // written as dataset 2411
/// assert_eq!((tip.definition_cs, tip.color), (0, 0));
/// ```
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Node {
    /// Node label (field 1).
    pub label: i64,
    /// Field 2: the definition coordinate system number (15), or the export coordinate
    /// system number (2411); 0 is the global system.
    pub definition_cs: i32,
    /// Field 3: the displacement coordinate system number.
    pub displacement_cs: i32,
    /// Field 4: the colour.
    pub color: i32,
    /// X coordinate, in the definition (15) or part (2411) coordinate system.
    pub x: f64,
    /// Y coordinate.
    pub y: f64,
    /// Z coordinate.
    pub z: f64,
    /// The dataset: [`Precision::Single`] for 15 (`E13.5`: 6 or 7 significant digits),
    /// [`Precision::Double`] for 2411 (`D25.16`: exact).
    pub precision: Precision,
}

/// Data at nodes: dataset 55, e.g. one mode shape.
///
/// `values[k]` holds the `values_per_node` values at node `nodes[k]`, as `(re, im)` (`im` is
/// 0 for real data): for a 3 DOF vector (data characteristic 2) X, Y, Z; for a 6 DOF one
/// (3) X, Y, Z, RX, RY, RZ. Nodes left out of the file have, by the description, all
/// values 0.
///
/// ```
/// use msd_uff::{Analysis55, Data55};
///
/// let mut mode = Data55::default(); // a real normal mode, 3 displacements per node
/// mode.analysis = Analysis55::NormalMode {
///     load_case: 1, mode: 1, frequency: 28.47, modal_mass: 1.25,
///     viscous_damping: 0.0078, hysteretic_damping: 0.0,
/// };
/// mode.nodes = vec![1, 2];
/// mode.values = vec![
///     vec![(0.0, 0.0), (-0.004, 0.0), (0.34, 0.0)],
///     vec![(0.0, 0.0), (-0.016, 0.0), (0.63, 0.0)],
/// ];
/// assert_eq!(mode.value(2, 3), Some((0.63, 0.0))); // node 2, +Z
/// assert_eq!(mode.to_string(), "normal mode 1 at 28.47 Hz, 2 nodes × 3 real values");
/// let file = msd_uff::UffFile { data_at_nodes: vec![mode], ..Default::default() };
/// let back = msd_uff::parse(&msd_uff::to_bytes(&file, &Default::default())?)?;
/// assert_eq!(back, file);
/// # Ok::<(), msd_uff::UffError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Data55 {
    /// ID lines 1–5 (records 1–5, up to 80 characters each). By convention: 1 the model,
    /// 2 the run, 3 the date and time, 4 the load case name; `"NONE"` when unused.
    pub ids: [String; 5],
    /// Record 6, field 1: model type: 0 unknown, 1 structural, 2 heat transfer, 3 fluid
    /// flow.
    pub model_type: i32,
    /// Record 6, field 2 (analysis type), with records 7 and 8 (its parameters).
    pub analysis: Analysis55,
    /// Record 6, field 3: data characteristic: 0 unknown, 1 scalar, 2 3 DOF global
    /// translation vector, 3 6 DOF global translation and rotation vector, 4 symmetric
    /// global tensor, 5 general global tensor.
    pub data_characteristic: i32,
    /// Record 6, field 4: specific data type: 0 unknown, 1 general, 2 stress, 3 strain,
    /// 4 element force, 5 temperature, 6 heat flux, 7 strain energy, 8 displacement,
    /// 9 reaction force, 10 kinetic energy, 11 velocity, 12 acceleration, 13 strain energy
    /// density (excitation force in I-DEAS Test), 14 kinetic energy density, 15
    /// hydro-static pressure, 16 heat gradient, 17 code checking value, 18 coefficient of
    /// pressure.
    pub specific_data_type: i32,
    /// Record 6, field 5: data type 5 (complex) if true, 2 (real) if false.
    pub complex: bool,
    /// Record 6, field 6: number of data values per node (1 scalar, 3 or 6 vector, 6
    /// symmetric tensor, 9 general tensor).
    pub values_per_node: usize,
    /// Record 9 of each node: the node numbers, in file order.
    pub nodes: Vec<i64>,
    /// Record 10 of each node: `values[k]` holds the values at `nodes[k]` as `(re, im)`.
    pub values: Vec<Vec<(f64, f64)>>,
}

impl Default for Data55 {
    /// A real normal mode (analysis type 2, mode 0 at 0 Hz) of 3 displacements per node
    /// (data characteristic 2, specific data type 8) on a structural model, no nodes, ID
    /// lines `"NONE"`.
    fn default() -> Self {
        let none = || "NONE".to_string();
        Self {
            ids: [none(), none(), none(), none(), none()],
            model_type: 1,
            analysis: Analysis55::NormalMode {
                load_case: 0,
                mode: 0,
                frequency: 0.0,
                modal_mass: 0.0,
                viscous_damping: 0.0,
                hysteretic_damping: 0.0,
            },
            data_characteristic: 2,
            specific_data_type: 8,
            complex: false,
            values_per_node: 3,
            nodes: Vec::new(),
            values: Vec::new(),
        }
    }
}

impl Data55 {
    /// Value `direction` (1-based: 1 X, 2 Y, 3 Z, 4 RX, … for a vector) at the node
    /// numbered `node`, as `(re, im)`; `None` if the node is not in the dataset or has no
    /// such value.
    ///
    /// ```
    /// let mut shape = msd_uff::Data55::default();
    /// shape.nodes = vec![7];
    /// shape.values = vec![vec![(0.1, 0.0), (0.2, 0.0), (0.3, 0.0)]];
    /// assert_eq!(shape.value(7, 2), Some((0.2, 0.0)));
    /// assert_eq!((shape.value(7, 0), shape.value(7, 4), shape.value(8, 1)), (None, None, None));
    /// ```
    pub fn value(&self, node: i64, direction: usize) -> Option<(f64, f64)> {
        let k = self.nodes.iter().position(|&n| n == node)?;
        self.values.get(k)?.get(direction.checked_sub(1)?).copied()
    }
}

/// The analysis type of a [`Data55`] (record 6, field 2) and its parameters (records 7
/// and 8).
///
/// Record 7 holds the number of integer parameters, the number of real ones, then the
/// integers; record 8 the reals. The types whose counts are those of the description are
/// read into their own variant; every other one, or one with other counts, is kept as
/// [`Analysis55::Other`], and written back as it was read.
///
/// ```
/// use msd_uff::Analysis55;
///
/// let a = Analysis55::from_parameters(2, vec![1, 3], vec![42.5, 0.8, 0.02, 0.0]);
/// assert!(matches!(a, Analysis55::NormalMode { mode: 3, frequency: 42.5, .. }));
/// assert_eq!((a.code(), a.integers(), a.reals()), (2, vec![1, 3], vec![42.5, 0.8, 0.02, 0.0]));
///
/// let statics = Analysis55::from_parameters(1, vec![4], vec![0.0]);
/// assert_eq!(statics, Analysis55::Other { analysis_type: 1, integers: vec![4], reals: vec![0.0] });
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Analysis55 {
    /// Analysis type 2, normal mode: record 7 `2 4 load_case mode`, record 8 the four
    /// reals below.
    NormalMode {
        /// Load case number.
        load_case: i64,
        /// Mode number.
        mode: i64,
        /// Frequency (Hz).
        frequency: f64,
        /// Modal mass.
        modal_mass: f64,
        /// Modal viscous damping ratio.
        viscous_damping: f64,
        /// Modal hysteretic damping ratio.
        hysteretic_damping: f64,
    },
    /// Analysis type 3 (complex eigenvalue, first order) or 7 (second order): record 7
    /// `2 6 load_case mode`, record 8 the eigenvalue, modal A and modal B, each real part
    /// then imaginary part.
    ComplexEigenvalue {
        /// Analysis type 7 (second order) if true, 3 (first order) if false.
        second_order: bool,
        /// Load case number.
        load_case: i64,
        /// Mode number.
        mode: i64,
        /// The eigenvalue `(re, im)`.
        eigenvalue: (f64, f64),
        /// Modal A `(re, im)`.
        modal_a: (f64, f64),
        /// Modal B `(re, im)`.
        modal_b: (f64, f64),
    },
    /// Analysis type 5, frequency response: record 7 `2 1 load_case frequency_step`,
    /// record 8 the frequency.
    FrequencyResponse {
        /// Load case number.
        load_case: i64,
        /// Frequency step number.
        frequency_step: i64,
        /// Frequency (Hz).
        frequency: f64,
    },
    /// Any other analysis type (0 unknown, 1 static, 4 transient, 6 buckling, …), or one of
    /// the above whose record 7 counts differ from the description's: the parameters as
    /// found.
    Other {
        /// Record 6, field 2.
        analysis_type: i32,
        /// Record 7, fields 3 and on (at most 10).
        integers: Vec<i64>,
        /// Record 8 (at most 12).
        reals: Vec<f64>,
    },
}

impl Analysis55 {
    /// The analysis type from its code and parameters (record 7 from field 3 on, and
    /// record 8): a variant of its own when the counts are the description's, else
    /// [`Analysis55::Other`].
    ///
    /// ```
    /// use msd_uff::Analysis55;
    /// let a = Analysis55::from_parameters(3, vec![1, 2], vec![-1.4, 178.9, 0.0, 447.2, 8e4, 626.1]);
    /// assert!(matches!(a, Analysis55::ComplexEigenvalue {
    ///     second_order: false, mode: 2, eigenvalue: (-1.4, 178.9), .. }));
    /// let odd = Analysis55::from_parameters(2, vec![1, 2, 3], vec![1.0; 4]); // 3 integers
    /// assert!(matches!(odd, Analysis55::Other { analysis_type: 2, .. }));
    /// ```
    pub fn from_parameters(analysis_type: i32, integers: Vec<i64>, reals: Vec<f64>) -> Self {
        match (analysis_type, integers.as_slice(), reals.as_slice()) {
            (2, &[load_case, mode], &[frequency, modal_mass, viscous, hysteretic]) => {
                Self::NormalMode {
                    load_case,
                    mode,
                    frequency,
                    modal_mass,
                    viscous_damping: viscous,
                    hysteretic_damping: hysteretic,
                }
            }
            (3 | 7, &[load_case, mode], &[e_re, e_im, a_re, a_im, b_re, b_im]) => {
                Self::ComplexEigenvalue {
                    second_order: analysis_type == 7,
                    load_case,
                    mode,
                    eigenvalue: (e_re, e_im),
                    modal_a: (a_re, a_im),
                    modal_b: (b_re, b_im),
                }
            }
            (5, &[load_case, frequency_step], &[frequency]) => Self::FrequencyResponse {
                load_case,
                frequency_step,
                frequency,
            },
            _ => Self::Other {
                analysis_type,
                integers,
                reals,
            },
        }
    }

    /// The analysis type code (record 6, field 2).
    ///
    /// ```
    /// let a = msd_uff::Analysis55::FrequencyResponse { load_case: 1, frequency_step: 4, frequency: 12.0 };
    /// assert_eq!(a.code(), 5);
    /// ```
    pub fn code(&self) -> i32 {
        match self {
            Self::NormalMode { .. } => 2,
            Self::ComplexEigenvalue { second_order, .. } => {
                if *second_order {
                    7
                } else {
                    3
                }
            }
            Self::FrequencyResponse { .. } => 5,
            Self::Other { analysis_type, .. } => *analysis_type,
        }
    }

    /// The integer parameters: record 7 from field 3 on.
    ///
    /// ```
    /// let a = msd_uff::Analysis55::FrequencyResponse { load_case: 1, frequency_step: 4, frequency: 12.0 };
    /// assert_eq!(a.integers(), [1, 4]);
    /// ```
    pub fn integers(&self) -> Vec<i64> {
        match self {
            Self::NormalMode {
                load_case, mode, ..
            }
            | Self::ComplexEigenvalue {
                load_case, mode, ..
            } => vec![*load_case, *mode],
            Self::FrequencyResponse {
                load_case,
                frequency_step,
                ..
            } => vec![*load_case, *frequency_step],
            Self::Other { integers, .. } => integers.clone(),
        }
    }

    /// The real parameters: record 8.
    ///
    /// ```
    /// let a = msd_uff::Analysis55::FrequencyResponse { load_case: 1, frequency_step: 4, frequency: 12.0 };
    /// assert_eq!(a.reals(), [12.0]);
    /// ```
    pub fn reals(&self) -> Vec<f64> {
        match self {
            Self::NormalMode {
                frequency,
                modal_mass,
                viscous_damping,
                hysteretic_damping,
                ..
            } => vec![
                *frequency,
                *modal_mass,
                *viscous_damping,
                *hysteretic_damping,
            ],
            Self::ComplexEigenvalue {
                eigenvalue: (e_re, e_im),
                modal_a: (a_re, a_im),
                modal_b: (b_re, b_im),
                ..
            } => vec![*e_re, *e_im, *a_re, *a_im, *b_re, *b_im],
            Self::FrequencyResponse { frequency, .. } => vec![*frequency],
            Self::Other { reals, .. } => reals.clone(),
        }
    }
}
