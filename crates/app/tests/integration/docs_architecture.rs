//! docs/ARCHITECTURE.md says what is: every file or folder it names exists, every constant it
//! quotes with a number (`` `NAME` (50 000) ``) has that value, and the size rule it states
//! (no source file over 600 lines) holds.

use std::path::{Path, PathBuf};

const ARCHITECTURE: &str = include_str!("../../../../docs/ARCHITECTURE.md");

/// The workspace root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The backticked words of `line`.
fn code_spans(line: &str) -> Vec<&str> {
    line.split('`').skip(1).step_by(2).collect()
}

/// Where a path named in the docs lives: `core/…` and `app/…` under `crates/`, the rest
/// (`tests/…`, `docs/…`) at the root.
fn located(path: &str) -> PathBuf {
    if path.starts_with("core/") || path.starts_with("app/") {
        root().join("crates").join(path)
    } else {
        root().join(path)
    }
}

/// Whether a code span names a file or folder (`scaled.rs`, `spatial/`, `core/src/gpu/rng.wgsl`).
fn is_path(span: &str) -> bool {
    let extension = Path::new(span)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    !span.contains(' ')
        && !span.contains("::")
        && !span.contains('*')
        && (span.ends_with('/') || matches!(extension.as_deref(), Some("rs" | "wgsl" | "md")))
}

#[test]
fn every_file_the_architecture_names_exists() {
    let mut missing = Vec::new();
    let mut checked = 0;
    for line in ARCHITECTURE.lines() {
        // A bare name is relative to the folder of the last full path on its line (or that
        // folder's parent: `core/src/walkthrough/`, `construction.rs`).
        let mut folder: Option<PathBuf> = None;
        for span in code_spans(line).into_iter().filter(|s| is_path(s)) {
            let full = span.starts_with("core/")
                || span.starts_with("app/")
                || span.starts_with("tests/")
                || span.starts_with("docs/");
            let found = if full {
                let path = located(span);
                folder = Some(if span.ends_with('/') {
                    path.clone()
                } else {
                    path.parent().map(Path::to_path_buf).unwrap_or_default()
                });
                path.exists()
            } else {
                folder.as_ref().is_some_and(|f| {
                    f.join(span).exists() || f.parent().is_some_and(|p| p.join(span).exists())
                })
            };
            checked += 1;
            if !found {
                missing.push(format!("`{span}` in: {line}"));
            }
        }
    }
    assert!(
        checked > 40,
        "only {checked} paths found: the parser lost the table"
    );
    assert!(
        missing.is_empty(),
        "named but missing:\n{}",
        missing.join("\n")
    );
}

#[test]
fn every_number_the_architecture_quotes_is_its_constant() {
    let constants: [(&str, usize); 2] = [
        ("SYNC_BUILD_LIMIT", lightpick::app::state::SYNC_BUILD_LIMIT),
        (
            "EXACT_TABLE_MAX_LIGHTS",
            lightpick::app::state::EXACT_TABLE_MAX_LIGHTS,
        ),
    ];
    let mut quoted = 0;
    for (name, value) in constants {
        let pattern = format!("`{name}` (");
        for (at, _) in ARCHITECTURE.match_indices(&pattern) {
            let digits: String = ARCHITECTURE[at + pattern.len()..]
                .chars()
                .take_while(|c| c.is_ascii_digit() || *c == ' ')
                .filter(char::is_ascii_digit)
                .collect();
            assert_eq!(
                digits.parse::<usize>().ok(),
                Some(value),
                "`{name}` quoted as {digits}"
            );
            quoted += 1;
        }
    }
    assert!(quoted >= 2, "the constants are quoted with their numbers");
    // No bare 65 536 left where the build limit is meant.
    assert!(!ARCHITECTURE.contains("65 536 lights it is built"));
}

#[test]
fn no_source_file_is_over_600_lines() {
    fn walk(dir: &Path, out: &mut Vec<(PathBuf, usize)>) {
        for entry in std::fs::read_dir(dir).expect("a folder") {
            let path = entry.expect("an entry").path();
            if path.is_dir() {
                if path.file_name().is_some_and(|n| n != "target") {
                    walk(&path, out);
                }
            } else if path.extension().is_some_and(|e| e == "rs") {
                let lines = std::fs::read_to_string(&path)
                    .expect("text")
                    .lines()
                    .count();
                out.push((path, lines));
            }
        }
    }
    let mut files = Vec::new();
    for top in ["crates", "tests"] {
        walk(&root().join(top), &mut files);
    }
    assert!(files.len() > 100);
    let long: Vec<String> = files
        .iter()
        .filter(|(_, n)| *n > 600)
        .map(|(p, n)| format!("{} ({n} lines)", p.display()))
        .collect();
    assert!(long.is_empty(), "over 600 lines:\n{}", long.join("\n"));
}
