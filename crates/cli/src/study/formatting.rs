//! Text for the studies' reports: numbers to a few significant digits and
//! spreads of them, the date and time, the machine's load and the command
//! line.

use super::measures::Spread;
use crate::json::Json;
use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

/// `value` with `digits` significant digits: fixed-point for magnitudes
/// from 10⁻⁴ to below 10⁶, else scientific (`1.23e-7`); `0` for zero and
/// `—` for NaN or infinity.
pub fn format_significant(value: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if !value.is_finite() {
        return "—".into();
    }
    if value == 0.0 {
        return "0".into();
    }
    let exponent = value.abs().log10().floor() as i32;
    if (-4..6).contains(&exponent) {
        let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
        let text = format!("{value:.decimals$}");
        // Rounding may carry into one more digit (9.995 -> 10.00): cut it.
        let significant = text
            .trim_start_matches(['-', '0', '.'])
            .chars()
            .filter(char::is_ascii_digit)
            .count();
        if decimals > 0 && significant > digits {
            format!("{value:.prec$}", prec = decimals - 1)
        } else {
            text
        }
    } else {
        format!("{value:.prec$e}", prec = digits - 1)
    }
}

/// A spread as `median [min, max]` with 4 significant digits.
pub fn spread_text(spread: &Spread) -> String {
    format!(
        "{} [{}, {}]",
        format_significant(spread.median, 4),
        format_significant(spread.min, 4),
        format_significant(spread.max, 4)
    )
}

/// A spread as a JSON object `{median, min, max}`.
pub fn spread_json(spread: &Spread) -> Json {
    Json::object(vec![
        ("median", Json::Number(spread.median)),
        ("min", Json::Number(spread.min)),
        ("max", Json::Number(spread.max)),
    ])
}

/// A relative value as a signed percentage with `digits` significant
/// digits, e.g. `+0.123 %`.
pub fn format_percentage(value: f64, digits: usize) -> String {
    if !value.is_finite() {
        return "—".into();
    }
    let text = format_significant(100.0 * value, digits);
    if value >= 0.0 {
        format!("+{text} %")
    } else {
        format!("{text} %")
    }
}

/// The time `time` in UTC as `YYYY-MM-DD HH:MM:SS UTC`.
pub fn utc_timestamp(time: SystemTime) -> String {
    let seconds = time
        .duration_since(UNIX_EPOCH)
        .map_or(0, |duration| duration.as_secs());
    let days = (seconds / 86_400) as i64;
    let second_of_day = seconds % 86_400;
    let (year, month, day) = civil_date(days);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC",
        second_of_day / 3600,
        second_of_day / 60 % 60,
        second_of_day % 60
    )
}

/// The proleptic Gregorian date (year, month, day) `days` after 1970-01-01,
/// counted in 400-year eras of 146 097 days that start on 1 March, so that
/// the leap day ends a year.
fn civil_date(days: i64) -> (i64, u32, u32) {
    const DAYS_PER_ERA: i64 = 146_097;
    // 1970-01-01 is 719 468 days after 0000-03-01.
    let days = days + 719_468;
    let era = days.div_euclid(DAYS_PER_ERA);
    let day_of_era = days.rem_euclid(DAYS_PER_ERA);
    // Years of 365 days, less a leap day every 4 years but every 100, plus
    // one every 400.
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    // Months from March: 31, 30, 31, 30, 31, 31, 30, 31, 30, 31, 31, 29/28.
    let month_from_march = (5 * day_of_year + 2) / 153;
    let day = (day_of_year - (153 * month_from_march + 2) / 5 + 1) as u32;
    let month = if month_from_march < 10 {
        month_from_march + 3
    } else {
        month_from_march - 9
    } as u32;
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// The load average over 1, 5 and 15 minutes as `a/b/c` (from
/// `/proc/loadavg`), or `unavailable`.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|text| {
            let fields: Vec<&str> = text.split_whitespace().take(3).collect();
            (fields.len() == 3).then(|| fields.join("/"))
        })
        .unwrap_or_else(|| "unavailable".into())
}

/// `argument` quoted for a POSIX shell where it needs it.
pub fn shell_quote(argument: &str) -> String {
    let plain = !argument.is_empty()
        && argument
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-+=.,:/@%".contains(c));
    if plain {
        argument.to_string()
    } else {
        format!("'{}'", argument.replace('\'', r"'\''"))
    }
}

/// This process's command line with the program called `lqmc`, quoted for
/// a shell, its paths as the user gave them but relative to the current
/// directory where they lie inside it ([`shown_path`]).
pub fn command_line() -> String {
    let current = std::env::current_dir().ok();
    std::iter::once("lqmc".to_string())
        .chain(std::env::args_os().skip(1).map(|argument| {
            shell_quote(&relative_argument(
                &argument.to_string_lossy(),
                current.as_deref(),
            ))
        }))
        .collect::<Vec<_>>()
        .join(" ")
}

/// `path` as a study writes it into its tables: as the user gave it, but an
/// absolute path inside the current directory relative to it, so that
/// tables written in a checkout name files by their place in it, not by
/// where the checkout lies.
pub fn shown_path(path: &Path) -> String {
    relative_path(path, std::env::current_dir().ok().as_deref())
}

/// `path` relative to `current` if it is absolute and inside it.
fn relative_path(path: &Path, current: Option<&Path>) -> String {
    match current.and_then(|current| path.strip_prefix(current).ok()) {
        Some(relative) if path.is_absolute() && !relative.as_os_str().is_empty() => {
            relative.display().to_string()
        }
        _ => path.display().to_string(),
    }
}

/// A command-line argument with its path (the argument itself, or the value
/// of `--option=VALUE`) relative to `current` where it lies inside it.
fn relative_argument(argument: &str, current: Option<&Path>) -> String {
    match argument.split_once('=') {
        Some((option, value)) if option.starts_with("--") => {
            format!("{option}={}", relative_path(Path::new(value), current))
        }
        _ => relative_path(Path::new(argument), current),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn significant_digits() {
        assert_eq!(format_significant(0.012345, 4), "0.01235");
        assert_eq!(format_significant(1.5, 4), "1.500");
        assert_eq!(format_significant(1234.4, 4), "1234");
        assert_eq!(format_significant(0.099996, 4), "0.1000");
        assert_eq!(format_significant(9.9996, 4), "10.00");
        assert_eq!(format_significant(1.234e-7, 3), "1.23e-7");
        assert_eq!(format_significant(-0.5, 2), "-0.50");
        assert_eq!(format_significant(0.0, 4), "0");
        assert_eq!(format_significant(f64::NAN, 4), "—");
        assert_eq!(format_percentage(0.001234, 3), "+0.123 %");
        assert_eq!(format_percentage(-0.02, 2), "-2.0 %");
    }

    #[test]
    fn timestamps_are_utc_dates() {
        assert_eq!(utc_timestamp(UNIX_EPOCH), "1970-01-01 00:00:00 UTC");
        let leap_day = UNIX_EPOCH + Duration::from_secs(951_782_400 + 3723);
        assert_eq!(utc_timestamp(leap_day), "2000-02-29 01:02:03 UTC");
        let later = UNIX_EPOCH + Duration::from_secs(1_798_761_599);
        assert_eq!(utc_timestamp(later), "2026-12-31 23:59:59 UTC");
    }

    #[test]
    fn paths_inside_the_current_directory_become_relative() {
        let current = Some(Path::new("/work/checkout"));
        let relative = |argument| relative_argument(argument, current);
        assert_eq!(relative("/work/checkout/docs/a.exr"), "docs/a.exr");
        assert_eq!(
            relative("--reference=/work/checkout/b.exr"),
            "--reference=b.exr"
        );
        assert_eq!(relative("/work/checkout"), "/work/checkout");
        assert_eq!(relative("/tmp/c.exr"), "/tmp/c.exr");
        assert_eq!(relative("out/d"), "out/d");
        assert_eq!(relative("builtin:cornell-box"), "builtin:cornell-box");
        assert_eq!(relative("--time"), "--time");
        assert_eq!(
            relative_argument("/work/checkout/e", None),
            "/work/checkout/e"
        );
    }

    #[test]
    fn arguments_are_quoted_where_needed() {
        assert_eq!(shell_quote("--time"), "--time");
        assert_eq!(shell_quote("builtin:cornell-box"), "builtin:cornell-box");
        assert_eq!(shell_quote("a b"), "'a b'");
        assert_eq!(shell_quote("it's"), r"'it'\''s'");
        assert_eq!(shell_quote(""), "''");
    }
}
