//! SHA-256 of the fixture files, and the `SHA256SUMS` list each fixture
//! folder carries (the format `sha256sum -c` reads), so a fixture changed
//! by hand or by a program stops the grader instead of grading against it.
//!
//! The hash itself is the `sha256` crate's (written from FIPS 180-4), built
//! optimised even in debug builds.

use std::path::Path;

pub use sha256::sha256_hex;

/// The name of the digest list in each fixture folder.
pub const SUMS_FILE: &str = "SHA256SUMS";

/// The `SHA256SUMS` text for these (file name, contents) pairs, sorted by
/// name.
pub fn sums_text(files: &[(String, Vec<u8>)]) -> String {
    let mut lines: Vec<String> = files
        .iter()
        .map(|(name, bytes)| format!("{}  {name}\n", sha256_hex(bytes)))
        .collect();
    lines.sort_by(|a, b| a[66..].cmp(&b[66..]));
    lines.concat()
}

/// Reads a folder's `SHA256SUMS`: (file name, digest) pairs.
pub fn read_sums(dir: &Path) -> Result<Vec<(String, String)>, String> {
    let path = dir.join(SUMS_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        format!(
            "{}: cannot read the digest list ({e}): restore the folder \
             (git checkout fixtures/) or ask a TA",
            path.display()
        )
    })?;
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            let (digest, name) = l.split_once("  ").ok_or_else(|| {
                format!("{}:{}: not a `DIGEST  NAME` line", path.display(), i + 1)
            })?;
            if digest.len() != 64 || !digest.bytes().all(|b| b.is_ascii_hexdigit()) {
                return Err(format!(
                    "{}:{}: not a SHA-256 digest",
                    path.display(),
                    i + 1
                ));
            }
            Ok((name.to_string(), digest.to_ascii_lowercase()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sums_file_round_trips() {
        let dir = std::env::temp_dir().join(format!("sums-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let text = sums_text(&[
            ("b.json".into(), b"2".to_vec()),
            ("a.json".into(), b"1".to_vec()),
        ]);
        assert!(text.starts_with(&sha256_hex(b"1")), "{text}");
        std::fs::write(dir.join(SUMS_FILE), &text).unwrap();
        let sums = read_sums(&dir).unwrap();
        assert_eq!(sums[0], ("a.json".to_string(), sha256_hex(b"1")));
        std::fs::write(dir.join(SUMS_FILE), "zz  a.json\n").unwrap();
        assert!(read_sums(&dir)
            .unwrap_err()
            .contains(":1: not a SHA-256 digest"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
