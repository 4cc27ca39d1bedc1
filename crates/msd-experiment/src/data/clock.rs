//! Clock times in a table's cells, as data loggers stamp their rows:
//! `12:00:00.002`, `2024-05-01 12:00:00.002`, `2024-05-01T12:00:00.002Z`,
//! `2024/05/01 12:00:00.002` or, in a European export, `01.05.2024 12:00:00,002` — read
//! as seconds (since midnight, or since 1970-01-01 with a date), which the time column
//! then counts from its first row.

/// Seconds of a clock time `H:MM:SS[.fff]` with an optional date before it (`YYYY-MM-DD`,
/// `YYYY/MM/DD` or `DD.MM.YYYY`, then a space or `T`) and an optional `Z` after it; the
/// fraction's mark is `decimal`. `None` for anything else (a time zone offset, a date
/// alone, minutes without seconds, a field out of range).
///
/// ```ignore
/// assert_eq!(clock_seconds("00:01:02.5", '.'), Some(62.5));
/// ```
pub(crate) fn clock_seconds(cell: &str, decimal: char) -> Option<f64> {
    let cell = cell.trim().strip_suffix('Z').unwrap_or(cell.trim());
    let (date, time) = match cell.rsplit_once([' ', 'T']) {
        Some((date, time)) => (Some(date.trim()), time),
        None => (None, cell),
    };
    let days = match date {
        Some(d) => days_of(d)?,
        None => 0,
    };
    let mut parts = time.splitn(3, ':');
    let (h, m, s) = (parts.next()?, parts.next()?, parts.next()?);
    let hours: u32 = digits(h, 1..=2)?;
    let minutes: u32 = digits(m, 2..=2)?;
    let (whole, fraction) = match s.split_once(decimal) {
        Some((w, f)) if !f.is_empty() && f.bytes().all(|b| b.is_ascii_digit()) => (w, f),
        Some(_) => return None,
        None => (s, ""),
    };
    let seconds: u32 = digits(whole, 2..=2)?;
    if hours > 23 || minutes > 59 || seconds > 60 {
        return None;
    }
    let fraction: f64 = match fraction {
        "" => 0.0,
        f => format!("0.{f}").parse().ok()?,
    };
    let whole = days * 86_400 + i64::from(hours * 3600 + minutes * 60 + seconds);
    Some(whole as f64 + fraction)
}

/// Whether `cell` is a clock time [`clock_seconds`] reads.
pub(crate) fn is_clock(cell: &str, decimal: char) -> bool {
    cell.contains(':') && clock_seconds(cell, decimal).is_some()
}

/// An unsigned number of `width` ASCII digits.
fn digits(text: &str, width: std::ops::RangeInclusive<usize>) -> Option<u32> {
    (width.contains(&text.len()) && text.bytes().all(|b| b.is_ascii_digit()))
        .then(|| text.parse().ok())
        .flatten()
}

/// Days from 1970-01-01 to a date `YYYY-MM-DD`, `YYYY/MM/DD` or `DD.MM.YYYY`.
fn days_of(date: &str) -> Option<i64> {
    let fields: Vec<&str> = date.split(['-', '/', '.']).collect();
    let [a, b, c] = fields.as_slice() else {
        return None;
    };
    let (y, m, d) = match date.contains('.') {
        true => (digits(c, 4..=4)?, digits(b, 1..=2)?, digits(a, 1..=2)?),
        false => (digits(a, 4..=4)?, digits(b, 1..=2)?, digits(c, 1..=2)?),
    };
    let leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    let length = [
        31,
        28 + u32::from(leap),
        31,
        30,
        31,
        30,
        31,
        31,
        30,
        31,
        30,
        31,
    ];
    if !(1..=12).contains(&m) || d == 0 || d > length[m as usize - 1] {
        return None;
    }
    Some(days_from_civil(i64::from(y), i64::from(m), i64::from(d)))
}

/// Days since 1970-01-01 of a date of the proleptic Gregorian calendar (Howard
/// Hinnant's `days_from_civil`).
fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_times_in_the_forms_loggers_write() {
        assert_eq!(clock_seconds("00:01:02.5", '.'), Some(62.5));
        assert_eq!(clock_seconds("9:00:00", '.'), Some(32_400.0));
        // 2024-05-01 is day 19 844 after 1970-01-01 (Python: date(2024,5,1).toordinal() − 719 163).
        let day = 19_844.0 * 86_400.0;
        assert_eq!(
            clock_seconds("2024-05-01 12:00:00.25", '.'),
            Some(day + 43_200.25)
        );
        assert_eq!(
            clock_seconds("2024-05-01T12:00:00.25Z", '.'),
            Some(day + 43_200.25)
        );
        assert_eq!(
            clock_seconds("2024/05/01 12:00:00.25", '.'),
            Some(day + 43_200.25)
        );
        assert_eq!(
            clock_seconds("01.05.2024 12:00:00,25", ','),
            Some(day + 43_200.25)
        );
        assert_eq!(days_from_civil(1970, 1, 1), 0);
        assert_eq!(days_from_civil(2000, 3, 1), 11_017);
        for not in [
            "12:00",
            "24:00:00",
            "12:60:00",
            "2024-02-30 12:00:00",
            "2024-05-01",
            "12:00:00+02:00",
            "12:00:00.",
            "1.5",
            "12:00:00,5",
        ] {
            assert_eq!(clock_seconds(not, '.'), None, "{not}");
        }
        assert!(is_clock("2023-02-28 23:59:59.999", '.'));
        assert_eq!(
            clock_seconds("2024-02-29 00:00:00", '.'),
            Some(19_782.0 * 86_400.0)
        );
    }
}
