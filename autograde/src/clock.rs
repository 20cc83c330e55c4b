//! Instants as the platforms write them: UTC ISO 8601 out (`result.json`'s
//! `datetime`, `commits.csv`), RFC 3339 in (a deadline, GitHub's and
//! Classroom 50's records of when something was handed in), and this
//! machine's clock. Civil dates by Howard Hinnant's algorithms: no crate
//! for twenty lines.

/// Seconds since the Unix epoch on this machine's clock (a runner's, a
/// TA's), never a time a student wrote.
pub fn now() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64)
}

/// UTC ISO 8601 of a Unix time: `2026-12-01T22:59:00Z`.
pub fn iso8601(secs: i64) -> String {
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// Days from 1970-01-01 to a civil date.
fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let doy = (153 * (if m > 2 { m - 3 } else { m + 9 }) + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

fn days_in_month(y: i64, m: i64) -> i64 {
    match m {
        2 if (y % 4 == 0 && y % 100 != 0) || y % 400 == 0 => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// A date and time with its zone, as Unix seconds: RFC 3339
/// (`2026-12-01T23:59:00+01:00`, `...Z`, fractions of a second ignored) and
/// the looser forms a person types (`2026-12-01 23:59 +0100`, seconds left
/// out, `UTC`). The zone is required: a deadline without one means
/// different instants on the TA's and the platform's machines. `None` for
/// anything else.
pub fn parse_instant(text: &str) -> Option<i64> {
    let t = text.trim();
    let num = |s: &str| -> Option<i64> {
        (!s.is_empty() && s.bytes().all(|b| b.is_ascii_digit()))
            .then(|| s.parse().ok())
            .flatten()
    };
    let (date, rest) = (t.get(..10)?, t.get(10..)?);
    let mut ymd = date.split('-');
    let (y, m, d) = (num(ymd.next()?)?, num(ymd.next()?)?, num(ymd.next()?)?);
    if date.len() != 10 || !(1..=12).contains(&m) || d < 1 || d > days_in_month(y, m) {
        return None;
    }
    let rest = rest.strip_prefix(['T', 't', ' '])?;
    // The clock: HH:MM or HH:MM:SS, then a fraction, then the zone.
    let clock_len = rest
        .find(|c: char| !(c.is_ascii_digit() || c == ':'))
        .unwrap_or(rest.len());
    let (clock, mut zone) = rest.split_at(clock_len);
    let parts: Vec<&str> = clock.split(':').collect();
    let (h, min, s) = match parts.as_slice() {
        [h, m] => (num(h)?, num(m)?, 0),
        [h, m, s] => (num(h)?, num(m)?, num(s)?),
        _ => return None,
    };
    if parts.iter().any(|p| p.len() != 2) || h > 23 || min > 59 || s > 60 {
        return None;
    }
    if let Some(frac) = zone.strip_prefix('.') {
        let digits = frac
            .find(|c: char| !c.is_ascii_digit())
            .unwrap_or(frac.len());
        if digits == 0 {
            return None;
        }
        zone = &frac[digits..];
    }
    let zone = zone.trim_start();
    let offset = match zone {
        "Z" | "z" | "UTC" | "GMT" => 0,
        _ => {
            let sign = match zone.as_bytes().first()? {
                b'+' => 1,
                b'-' => -1,
                _ => return None,
            };
            let z = &zone[1..];
            let (zh, zm) = match (z.len(), z.split_once(':')) {
                (5, Some((a, b))) if a.len() == 2 => (num(a)?, num(b)?),
                (4, None) => (num(&z[..2])?, num(&z[2..])?),
                (2, None) => (num(z)?, 0),
                _ => return None,
            };
            if zh > 23 || zm > 59 {
                return None;
            }
            sign * (zh * 3600 + zm * 60)
        }
    };
    Some(days_from_civil(y, m, d) * 86_400 + h * 3600 + min * 60 + s - offset)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iso8601_is_utc() {
        assert_eq!(iso8601(0), "1970-01-01T00:00:00Z");
        assert_eq!(iso8601(1_780_324_325), "2026-06-01T14:32:05Z");
    }

    #[test]
    fn instants_are_read_with_their_zone_and_back() {
        let at = parse_instant("2026-12-01T22:59:00Z").unwrap();
        assert_eq!(iso8601(at), "2026-12-01T22:59:00Z");
        for same in [
            "2026-12-01 23:59 +0100",
            "2026-12-01T23:59:00+01:00",
            "2026-12-01 23:59:00 +01",
            "2026-12-01T22:59:00.250Z",
            "2026-12-01 22:59 UTC",
            "2026-12-01T17:59:00-05:00",
        ] {
            assert_eq!(parse_instant(same), Some(at), "{same}");
        }
        assert_eq!(parse_instant("2024-02-29T00:00:00Z"), Some(1_709_164_800));
        for bad in [
            "2026-12-01 23:59",
            "2026-12-01",
            "2026-13-01T00:00Z",
            "2026-02-30T00:00Z",
            "2026-12-01T24:00Z",
            "2026-12-01T23:59+2",
            "tomorrow",
            "2026-12-01T23:59:00 +01:00 and more",
            "",
        ] {
            assert_eq!(parse_instant(bad), None, "{bad}");
        }
    }
}
