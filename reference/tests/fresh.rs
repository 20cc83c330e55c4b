//! Fresh cases: random meshes per submission, the same for the same seed,
//! passed by correct implementations and failed by a lookup table of the
//! visible cases.

use std::path::Path;

mod common;
use common::*;

fn fresh(seed: &str, dir: &Path) {
    let r = run(&["fresh", "--seed", seed, "--dir", dir.to_str().unwrap()]);
    assert_eq!(r.code, 0, "{}", r.stderr);
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for group in ["hidden", "bonus"] {
        for e in std::fs::read_dir(dir.join(group)).unwrap() {
            let p = e.unwrap().path();
            out.push((
                format!("{group}/{}", p.file_name().unwrap().to_string_lossy()),
                std::fs::read(&p).unwrap(),
            ));
        }
    }
    out.sort();
    out
}

#[test]
fn a_seed_gives_the_same_cases_and_another_seed_other_meshes() {
    let dir = scratch("fresh-seeds");
    let (a, b, c) = (dir.join("a"), dir.join("b"), dir.join("c"));
    fresh("00000000deadbeef", &a);
    fresh("deadbeef", &b);
    fresh("1", &c);
    assert_eq!(files(&a), files(&b), "the same seed, byte for byte");
    let names: Vec<String> = files(&a).into_iter().map(|(n, _)| n).collect();
    assert!(
        names
            .iter()
            .all(|n| n.ends_with("SHA256SUMS") || n.contains("fresh-00000000deadbeef-")),
        "named by their seed: {names:?}"
    );
    let input =
        |dir: &Path, name: &str| json(&dir.join("hidden").join(name))["input"]["positions"].clone();
    assert_ne!(
        input(&a, "fresh-00000000deadbeef-icosphere-flip.json"),
        input(&c, "fresh-0000000000000001-icosphere-flip.json"),
        "another seed moves the vertices elsewhere"
    );
    // No fresh input is a visible case's input.
    let visible: Vec<serde_json::Value> = ["lab", "bonus"]
        .iter()
        .flat_map(|g| case_files(g))
        .map(|p| json(&p)["input"]["positions"].clone())
        .collect();
    for (name, bytes) in files(&a) {
        if name.ends_with(".json") {
            let f: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
            assert!(!visible.contains(&f["input"]["positions"]), "{name}");
        }
    }
    let bad = run(&["fresh", "--seed", "xyz", "--dir", dir.to_str().unwrap()]);
    assert_eq!(bad.code, 2);
    assert!(
        bad.stderr.contains("a seed is 1 to 16 hex digits"),
        "{}",
        bad.stderr
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn correct_implementations_pass_fresh_cases_and_a_lookup_table_fails_every_one() {
    let dir = scratch("fresh-grade");
    for seed in ["1", "2", "c0ffee"] {
        let d = dir.join(seed);
        fresh(seed, &d);
        let fixtures = d.to_str().unwrap();
        for name in ["reference", "alt-order", "alt-reverse"] {
            let g = grade(name, &["--fixtures", fixtures, "--bonus"]);
            assert_eq!(g.code, 0, "{name} on seed {seed}:\n{}", g.stdout);
        }
        let g = grade("lookup-table", &["--fixtures", fixtures, "--bonus", "-q"]);
        assert_eq!(g.code, 1, "{}", g.stdout);
        for line in g.stdout.lines().filter(|l| l.contains("cases passed: ")) {
            for tally in line.split("passed: ").nth(1).unwrap().split(", ") {
                assert!(
                    tally.contains(" 0/"),
                    "the table scores 0 on fresh cases: {line}"
                );
            }
        }
    }
    // The same table passes every visible case.
    let visible = dir.join("visible");
    for g in ["lab", "bonus"] {
        std::fs::create_dir_all(visible.join(g)).unwrap();
        for e in std::fs::read_dir(lab_root().join("fixtures").join(g)).unwrap() {
            let p = e.unwrap().path();
            std::fs::copy(&p, visible.join(g).join(p.file_name().unwrap())).unwrap();
        }
    }
    let g = grade(
        "lookup-table",
        &["--fixtures", visible.to_str().unwrap(), "--bonus"],
    );
    assert_eq!(
        g.code, 0,
        "the table knows the visible cases:\n{}",
        g.stdout
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_seed_follows_the_secret_and_the_submission() {
    use reference::fresh::seed_for;
    let a = seed_for(b"hidden sums", b"fn flip_edge() {}");
    assert_eq!(a, seed_for(b"hidden sums", b"fn flip_edge() {}"));
    assert_ne!(a, seed_for(b"hidden sums", b"fn flip_edge() { }"));
    assert_ne!(a, seed_for(b"other sums", b"fn flip_edge() {}"));
    // The lab's secret is its hidden cases' digest list.
    let secret = reference::fresh::secret_of(&lab_root().join("fixtures")).unwrap();
    assert_eq!(
        secret,
        std::fs::read(lab_root().join("fixtures/hidden/SHA256SUMS")).unwrap()
    );
    let missing = reference::fresh::secret_of(Path::new("/no/such/fixtures")).unwrap_err();
    assert!(
        missing.contains("the secret fresh cases are drawn from"),
        "{missing}"
    );
}
