//! Write → read: exact where the format can be, and within the documented digits where
//! its columns are too narrow.

use msd_uff::{
    Abscissa, AsciiNumbers, ByteOrder, Encoding, Function58, FunctionType, Ordinate, Precision,
    UffError, UffFile, WriteOptions,
};
use proptest::prelude::*;

use crate::sample_file;

const FIXED: WriteOptions = WriteOptions {
    ascii: AsciiNumbers::Fixed,
};
const EXACT: WriteOptions = WriteOptions {
    ascii: AsciiNumbers::Exact,
};

fn round_trip(file: &UffFile, options: &WriteOptions) -> UffFile {
    let bytes = msd_uff::to_bytes(file, options).expect("write");
    let back = msd_uff::parse(&bytes).expect("read back");
    assert!(
        msd_uff::to_bytes(&back, options).expect("write again") == bytes,
        "writing what was read changes the file"
    );
    back
}

/// Every number of a function: abscissa start and step or values, z value, ordinate parts.
fn numbers(f: &Function58) -> Vec<f64> {
    let mut v = match &f.abscissa {
        Abscissa::Even { start, step } => vec![*start, *step],
        Abscissa::Uneven(x) => x.clone(),
    };
    v.push(f.z_axis_value);
    match &f.ordinate {
        Ordinate::Real(y) => v.extend(y),
        Ordinate::Complex(y) => v.extend(y.iter().flat_map(|&(re, im)| [re, im])),
    }
    v
}

/// The function with its numbers replaced by zeros, to compare everything else.
fn without_numbers(f: &Function58) -> Function58 {
    let mut f = f.clone();
    f.z_axis_value = 0.0;
    f.abscissa = match f.abscissa {
        Abscissa::Even { .. } => Abscissa::Even {
            start: 0.0,
            step: 0.0,
        },
        Abscissa::Uneven(x) => Abscissa::Uneven(vec![0.0; x.len()]),
    };
    f.ordinate = match f.ordinate {
        Ordinate::Real(y) => Ordinate::Real(vec![0.0; y.len()]),
        Ordinate::Complex(y) => Ordinate::Complex(vec![(0.0, 0.0); y.len()]),
    };
    f
}

fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / a.abs().max(b.abs())
    }
}

#[test]
fn binary_double_and_exact_ascii_round_trip_identically() {
    let binary = sample_file(Encoding::Binary(ByteOrder::Little));
    let mut doubles = binary.clone();
    doubles
        .functions
        .iter_mut()
        .for_each(|f| f.precision = Precision::Double);
    assert_eq!(round_trip(&doubles, &EXACT), doubles);
    let ascii = sample_file(Encoding::Ascii);
    let mut ascii_doubles = ascii.clone();
    ascii_doubles
        .functions
        .iter_mut()
        .for_each(|f| f.precision = Precision::Double);
    assert_eq!(round_trip(&ascii_doubles, &EXACT), ascii_doubles);
    // Single precision in Exact ASCII keeps the f64 values too: only binary rounds them.
    assert_eq!(round_trip(&ascii, &EXACT), ascii);
}

#[test]
fn binary_double_data_round_trips_to_the_bit_with_the_default_options() {
    // With AsciiNumbers::Fixed only record 7's start and step are text; the data is exact.
    let mut file = sample_file(Encoding::Binary(ByteOrder::Little));
    file.functions
        .iter_mut()
        .for_each(|f| f.precision = Precision::Double);
    let specials = [
        f64::NAN,
        -0.0,
        5e-324,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MAX,
        -1.0 / 3.0,
    ];
    file.functions[4].ordinate = Ordinate::Real(specials.to_vec());
    let back = round_trip(&file, &FIXED);
    for (a, b) in file.functions.iter().zip(&back.functions) {
        let (a, b) = (&a.ordinate, &b.ordinate);
        let bits = |o: &Ordinate| -> Vec<u64> {
            match o {
                Ordinate::Real(y) => y.iter().map(|v| v.to_bits()).collect(),
                Ordinate::Complex(y) => y
                    .iter()
                    .flat_map(|(r, i)| [r.to_bits(), i.to_bits()])
                    .collect(),
            }
        };
        assert_eq!(bits(a), bits(b));
    }
    // The abscissa step 0.1220703125 needs 10 digits: the 13 columns of record 7 hold 7.
    assert_eq!(
        back.functions[3].abscissa,
        Abscissa::Even {
            start: 0.0,
            step: 0.1220703
        }
    );
    assert_eq!(
        back.functions[4].abscissa,
        Abscissa::Even {
            start: -0.25,
            step: 1.0 / 1024.0
        }
    );
}

#[test]
fn binary_single_precision_rounds_to_f32_and_then_round_trips() {
    let file = sample_file(Encoding::Binary(ByteOrder::Little));
    let back = round_trip(&file, &EXACT);
    let (sent, got) = (&file.functions[2], &back.functions[2]);
    assert_eq!(got.precision, Precision::Single);
    let (Ordinate::Complex(y0), Ordinate::Complex(y1)) = (&sent.ordinate, &got.ordinate) else {
        panic!("complex")
    };
    for (&(r0, i0), &(r1, i1)) in y0.iter().zip(y1) {
        assert_eq!((r0 as f32 as f64, i0 as f32 as f64), (r1, i1));
    }
    let (Abscissa::Uneven(x0), Abscissa::Uneven(x1)) = (&sent.abscissa, &got.abscissa) else {
        panic!("uneven")
    };
    assert!(x0.iter().zip(x1).all(|(&a, &b)| a as f32 as f64 == b));
    assert_eq!(round_trip(&back, &EXACT), back); // already f32: exact from here on
}

#[test]
fn fixed_ascii_keeps_the_digits_its_columns_hold() {
    let file = sample_file(Encoding::Ascii);
    let back = round_trip(&file, &FIXED);
    assert_eq!((&back.header, &back.units), (&file.header, &file.units));
    let mut worst = [0.0f64; 2]; // [20 columns, 13 columns]
    for (a, b) in file.functions.iter().zip(&back.functions) {
        assert_eq!(without_numbers(a), without_numbers(b));
        let narrow = a.precision == Precision::Single;
        let (na, nb) = (numbers(a), numbers(b));
        let header = match a.abscissa {
            Abscissa::Even { .. } => 3,
            Abscissa::Uneven(_) => 1, // z value; x is interleaved below
        };
        for (k, (&x, &y)) in na.iter().zip(&nb).enumerate() {
            let uneven_x = matches!(a.abscissa, Abscissa::Uneven(_)) && k < a.len();
            let wide = !narrow && k >= header && !uneven_x;
            let e = rel(x, y);
            worst[usize::from(!wide)] = worst[usize::from(!wide)].max(e);
        }
    }
    assert!(worst[0] <= 5e-13 && worst[0] > 0.0, "20 columns: {worst:?}");
    assert!(worst[1] <= 6e-6 && worst[1] > 0.0, "13 columns: {worst:?}");
    // Numbers with a short decimal form come back exactly.
    assert_eq!(back.functions[0].abscissa, file.functions[0].abscissa);
    assert_eq!(back.functions[4].abscissa, file.functions[4].abscissa);
    assert_eq!(back.units, file.units);
}

#[test]
fn the_writer_refuses_what_its_fields_cannot_hold() {
    let refuse = |edit: &dyn Fn(&mut Function58)| -> String {
        let mut file = sample_file(Encoding::Ascii);
        edit(&mut file.functions[1]);
        let err = msd_uff::to_bytes(&file, &FIXED).expect_err("refused");
        assert!(matches!(
            err,
            UffError::Unwritable {
                dataset: 58,
                index: 1,
                ..
            }
        ));
        err.to_string()
    };
    assert_eq!(
        refuse(&|f| f.abscissa = Abscissa::Uneven(vec![1.0, 2.0])),
        "cannot write dataset 58 (#1 of its kind): `abscissa` = 2 uneven values: expected one per ordinate value (9)"
    );
    assert_eq!(
        refuse(&|f| f.response_node = 12_345_678_901),
        "cannot write dataset 58 (#1 of its kind): `response_node` = 12345678901: expected an integer of at most 10 characters"
    );
    assert_eq!(
        refuse(&|f| f.ids[3] = "   -1".into()),
        "cannot write dataset 58 (#1 of its kind): `ids[3]` = \"   -1\": expected a text other than \"-1\", which closes a dataset"
    );
    assert_eq!(
        refuse(&|f| f.ordinate_axis.units = "m\ns".into()),
        "cannot write dataset 58 (#1 of its kind): `axis units` = \"m\\ns\": expected text without line breaks"
    );
    assert_eq!(
        refuse(&|f| f.function_type = FunctionType::Other(123_456)),
        "cannot write dataset 58 (#1 of its kind): `function_type` = 123456: expected an integer of at most 5 characters"
    );
    let mut file = sample_file(Encoding::Ascii);
    file.units.as_mut().expect("units").description = "twenty-one characters".into();
    assert_eq!(
        msd_uff::to_bytes(&file, &FIXED)
            .expect_err("refused")
            .to_string(),
        "cannot write dataset 164 (#0 of its kind): `description` = \"twenty-one characters\": expected at most 20 characters"
    );
}

/// Text without surrounding blanks or line breaks, which the fields keep exactly.
fn text(max: usize) -> impl Strategy<Value = String> {
    proptest::string::string_regex(&format!(
        "([A-Za-z0-9_./°²µ]([A-Za-z0-9 _./°²µ]{{0,{}}}[A-Za-z0-9_./°²µ])?)?",
        max.saturating_sub(2)
    ))
    .expect("regex")
    .prop_filter("not -1", |s| s != "-1")
}

fn function() -> impl Strategy<Value = Function58> {
    let number = prop_oneof![
        any::<f64>().prop_filter("finite", |v| v.is_finite()),
        -1e3..1e3f64
    ];
    (
        (any::<bool>(), any::<bool>(), any::<bool>(), 0..3u8),
        proptest::collection::vec((number.clone(), number.clone(), number.clone()), 0..30),
        (number.clone(), number.clone(), number),
        (text(80), text(10), text(20), text(20)),
        (-99_999i64..99_999, -9i32..10, 0i32..30),
    )
        .prop_map(
            |(
                (even, complex, single, encoding),
                points,
                (start, step, z),
                (id, entity, label, units),
                (node, dir, kind),
            )| {
                let abscissa = if even {
                    Abscissa::Even { start, step }
                } else {
                    Abscissa::Uneven(points.iter().map(|p| p.0).collect())
                };
                let ordinate = if complex {
                    Ordinate::Complex(points.iter().map(|p| (p.1, p.2)).collect())
                } else {
                    Ordinate::Real(points.iter().map(|p| p.1).collect())
                };
                let mut f = Function58::new(FunctionType::from_code(kind), abscissa, ordinate);
                f.precision = if single {
                    Precision::Single
                } else {
                    Precision::Double
                };
                f.encoding = [
                    Encoding::Ascii,
                    Encoding::Binary(ByteOrder::Little),
                    Encoding::Binary(ByteOrder::Big),
                ][encoding as usize];
                f.z_axis_value = z;
                f.ids[1] = id;
                (f.response_entity, f.response_node, f.response_direction) = (entity, node, dir);
                (f.ordinate_axis.label, f.ordinate_axis.units) = (label, units);
                f
            },
        )
}

/// What a function reads back as from a file written with `Exact`: single precision in
/// binary rounds to f32.
fn expected_back(f: &Function58) -> Function58 {
    let mut f = f.clone();
    if f.precision == Precision::Single && f.encoding != Encoding::Ascii {
        let r = |v: f64| v as f32 as f64;
        if let Abscissa::Uneven(x) = &mut f.abscissa {
            x.iter_mut().for_each(|v| *v = r(*v));
        }
        match &mut f.ordinate {
            Ordinate::Real(y) => y.iter_mut().for_each(|v| *v = r(*v)),
            Ordinate::Complex(y) => y.iter_mut().for_each(|(a, b)| (*a, *b) = (r(*a), r(*b))),
        }
    }
    f
}

proptest! {
    #[test]
    fn any_function_round_trips_exactly_with_exact_numbers(functions in proptest::collection::vec(function(), 1..4)) {
        let file = UffFile { functions, ..UffFile::default() };
        let bytes = msd_uff::to_bytes(&file, &EXACT).expect("write");
        let back = msd_uff::parse(&bytes).expect("read back");
        let expected: Vec<Function58> = file.functions.iter().map(expected_back).collect();
        prop_assert_eq!(back.functions, expected);
    }

    #[test]
    fn any_function_round_trips_within_the_columns_with_fixed_numbers(f in function()) {
        let file = UffFile { functions: vec![f], ..UffFile::default() };
        let bytes = msd_uff::to_bytes(&file, &FIXED).expect("write");
        let back = msd_uff::parse(&bytes).expect("read back");
        let (a, b) = (expected_back(&file.functions[0]), &back.functions[0]);
        prop_assert_eq!(without_numbers(&a), without_numbers(b));
        for (x, y) in numbers(&a).into_iter().zip(numbers(b)) {
            // 13 columns hold at least 5 significant digits; subnormals hold fewer.
            prop_assert!(rel(x, y) <= 5e-5 || (x - y).abs() < 1e-300, "{} {}", x, y);
        }
    }
}
