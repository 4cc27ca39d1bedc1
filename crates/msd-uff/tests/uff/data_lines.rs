//! Record 12 in ASCII as the reader takes it line by line: numbers bit-identical to the
//! text written, whatever the blanks, line ends and columns between them, and data lines
//! that are not all numbers refused at their line. (The errors' text is that of the reader
//! before its data lines were read without building a line each: 2026-11-26.)

use msd_uff::{
    Abscissa, AsciiNumbers, Function58, FunctionType, Ordinate, Precision, UffFile, WriteOptions,
};

/// Numbers of every kind: short and long decimals, extremes, subnormals, signed zeros.
fn values(n: usize, seed: u64) -> Vec<f64> {
    let mut state = seed | 1;
    (0..n)
        .map(|k| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            match k % 7 {
                0 => (state % 2001) as f64 / 8.0 - 125.0,
                // Any finite number, subnormals included.
                1 | 2 => {
                    f64::from_bits(state % f64::INFINITY.to_bits()) * (3.0 - 2.0 * (k % 7) as f64)
                }
                3 => [0.0, -0.0, f64::MAX, -f64::MIN_POSITIVE, 5e-324][(state % 5) as usize],
                _ => ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 1e3,
            }
        })
        .collect()
}

/// One function of each layout (real or complex, even or uneven, single or double).
fn file(n: usize) -> UffFile {
    let mut file = UffFile::default();
    for (k, (complex, even, precision)) in [false, true]
        .into_iter()
        .flat_map(|c| [(c, true), (c, false)])
        .flat_map(|(c, e)| [(c, e, Precision::Single), (c, e, Precision::Double)])
        .enumerate()
    {
        let v = values(n * 2, k as u64 + 1);
        let abscissa = if even {
            Abscissa::Even {
                start: 0.0,
                step: 0.5,
            }
        } else {
            Abscissa::Uneven(values(n, k as u64 + 100))
        };
        let ordinate = if complex {
            Ordinate::Complex(v.chunks_exact(2).map(|p| (p[0], p[1])).collect())
        } else {
            Ordinate::Real(v[..n].to_vec())
        };
        let mut f = Function58::new(FunctionType::FrequencyResponse, abscissa, ordinate);
        f.precision = precision;
        file.functions.push(f);
    }
    file
}

/// The numbers of record 12 of every function, as read.
fn data(file: &UffFile) -> Vec<u64> {
    let mut out = Vec::new();
    for f in &file.functions {
        let x = match &f.abscissa {
            Abscissa::Uneven(x) => x.clone(),
            Abscissa::Even { .. } => Vec::new(),
        };
        let parts: Vec<f64> = match &f.ordinate {
            Ordinate::Real(y) => y.clone(),
            Ordinate::Complex(y) => y.iter().flat_map(|&(re, im)| [re, im]).collect(),
        };
        let per = parts.len() / x.len().max(1);
        for (k, chunk) in parts.chunks(per.max(1)).enumerate() {
            out.extend(x.get(k).map(|v| v.to_bits()));
            out.extend(chunk.iter().map(|v| v.to_bits()));
        }
    }
    out
}

/// The numbers of the data lines of `text` as the standard library reads each word: the
/// lines after record 11 (the twelfth line of a dataset) up to the closing `    -1`.
fn words_as_std_reads_them(text: &str) -> Vec<u64> {
    let mut out = Vec::new();
    let mut line_in_dataset = 0;
    for line in text.lines() {
        line_in_dataset += 1;
        if line.trim() == "-1" {
            line_in_dataset = if line_in_dataset > 1 { 0 } else { 1 };
            continue;
        }
        if line_in_dataset > 13 {
            let words = line.split_whitespace();
            out.extend(words.map(|w| w.parse::<f64>().expect("a number").to_bits()));
        }
    }
    out
}

/// `got == expected`, naming the first number that differs.
fn assert_same(got: &[u64], expected: &[u64]) {
    let first = got.iter().zip(expected).position(|(a, b)| a != b);
    if let Some(k) = first {
        let (a, b) = (f64::from_bits(got[k]), f64::from_bits(expected[k]));
        panic!("number {k}: read {a:e}, expected {b:e}");
    }
    assert_eq!(got.len(), expected.len());
}

#[test]
fn numbers_read_back_bit_identical_to_the_text_written() {
    let original = file(3001);
    // Exact: every number is read back as written.
    let exact = msd_uff::to_bytes(
        &original,
        &WriteOptions {
            ascii: AsciiNumbers::Exact,
        },
    );
    let back = msd_uff::parse(&exact.expect("written")).expect("read");
    assert_same(&data(&back), &data(&original));
    // Fixed: every number is read as the standard library reads its text.
    let fixed = msd_uff::to_bytes(&original, &WriteOptions::default()).expect("written");
    let back = msd_uff::parse(&fixed).expect("read");
    let text = String::from_utf8(fixed).expect("text");
    assert_same(&data(&back), &words_as_std_reads_them(&text));
}

/// The file with every blank run between two numbers of its data lines replaced by `blank`
/// (the lines that start with a blank and hold an `E`), and its line ends by `end`.
fn respaced(text: &str, blank: &str, end: &str) -> Vec<u8> {
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            if l.starts_with(' ') && l.contains('E') && !l.contains("NONE") {
                let words: Vec<&str> = l.split_whitespace().collect();
                format!(" {}", words.join(blank))
            } else {
                l.to_string()
            }
        })
        .collect();
    (lines.join(end) + end).into_bytes()
}

#[test]
fn any_blanks_and_line_ends_read_the_same_numbers() {
    let original = file(17);
    let bytes = msd_uff::to_bytes(&original, &WriteOptions::default()).expect("written");
    let text = String::from_utf8(bytes).expect("text");
    let read = msd_uff::parse(text.as_bytes()).expect("read");
    let latin1 = |b: &[u8]| -> Vec<u8> {
        b.iter()
            .map(|&c| if c == b'~' { 0xA0 } else { c })
            .collect()
    };
    for (blank, end) in [
        ("\t", "\n"),
        ("  \x0b ", "\r\n"),
        ("\x0c", "\r"),
        ("\u{a0}", "\n"), // a blank to `char::is_whitespace`, not ASCII
        ("\u{2003} ", "\r\n"),
        (" ", "\n"),
    ] {
        let variant = respaced(&text, blank, end);
        let got = msd_uff::parse(&variant).expect("read");
        assert_eq!(data(&got), data(&read), "{blank:?} {end:?}");
    }
    // A Latin-1 no-break space (byte 0xA0, not UTF-8) between numbers reads alike.
    let got = msd_uff::parse(&latin1(&respaced(&text, "~", "\n"))).expect("read");
    assert_eq!(data(&got), data(&read));
}

/// A complex dataset 58 of `points` points, double precision, with these data lines.
fn dataset(points: usize, data: &[&str]) -> String {
    let mut lines = vec![
        "    -1".to_string(),
        "    58".into(),
        "NONE".into(),
        "NONE".into(),
        "NONE".into(),
        "NONE".into(),
        "NONE".into(),
        "    4         0    0         0       NONE         1   3       NONE         1   3".into(),
        format!("         6{points:>10}         1  0.00000e+00  1.00000e+00  0.00000e+00"),
    ];
    for _ in 8..12 {
        lines.push("         0    0    0    0 NONE                 NONE".into());
    }
    lines.extend(data.iter().map(|l| l.to_string()));
    lines.push("    -1".into());
    lines.join("\n") + "\n"
}

#[test]
fn numbers_that_touch_are_read_in_the_columns_of_the_format() {
    let text = dataset(
        3,
        &[
            // 4E20.12 filled to the last column: no blank between the numbers.
            "-1.2345678901234E-01 12345.678901234D+00-0.1234567890123-100",
            "  1.0E+00  2.0E+00",
            "\t-1.5 ",
        ],
    );
    let file = msd_uff::parse(text.as_bytes()).expect("read");
    let Ordinate::Complex(y) = &file.functions[0].ordinate else {
        panic!("complex")
    };
    let expected = [
        (-0.12345678901234, 12345.678901234),
        (-0.1234567890123e-100, 1.0),
        (2.0, -1.5),
    ];
    assert_eq!(y, &expected);
}

#[test]
fn data_lines_that_are_not_all_numbers_are_refused_where_they_are() {
    for (data, error) in [
        (
            &["  1.0E+00  2.0E+00", "  3.0E+00 x4.0E+00", "  5.0 6.0"][..],
            "dataset 58, byte 427, line 15: record 12, data value: found \"x4.0E+00\", expected a number",
        ),
        (
            &["  1.0E+00  2.0E+00", "    -1", "  5.0 6.0"],
            "dataset 58, byte 417, line 15: record 12 (data values): found 2 values, expected 6 values (re, im per point)",
        ),
        (
            &["  1.0E+00  2.0E+00  3.0 4.0", "  -1 2.0 3.0"],
            "dataset 58, byte 426, line 15: record 12 (data values): found more than 6 values by this line, expected 6 values (re, im per point)",
        ),
    ] {
        let err = msd_uff::parse(dataset(3, data).as_bytes()).expect_err("refused");
        assert_eq!(err.to_string(), error);
    }
}
