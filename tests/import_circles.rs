//! No import circles: no source file of a crate imports, directly or through others, from a
//! file that imports from it (docs/ARCHITECTURE.md: each file shows what it may touch).
//!
//! The check reads the `use` lines and the paths written in code (`super::x::f()`,
//! `crate::numbers::short(v)`) of every `.rs` file under `crates/*/src`, comments aside (a
//! declaration `mod x;` is not an import; a `pub use` re-export is). A path is resolved to the file of
//! its longest module prefix: `crate::app::state::edit::power_to_text` in the `lightpick`
//! crate is `src/app/state/edit.rs`; `super::x` and `self::x` from the file's own module.
//! A bare path names a child module (`use rebuild::TableBuild;` in a `mod.rs`). A module's
//! imports of its own descendants are not edges: a facade (`lib.rs`, a `mod.rs`) re-exporting
//! its children is how a module shows its API; a child reaching a sibling through the
//! facade (`use crate::Scaled` in a file beside `scaled.rs`) is an edge to the facade. The
//! strongly connected components of that graph must all be single files.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// One crate's files by module path (`["app", "state", "edit"]` → its file).
struct Crate {
    modules: BTreeMap<Vec<String>, PathBuf>,
}

/// The module path of `file` under `src` (`lib.rs`, `main.rs` and `mod.rs` name their
/// folder).
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let relative = file.strip_prefix(src).expect("under src");
    let mut parts: Vec<String> = relative
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().expect("a file name");
    let stem = last.trim_end_matches(".rs");
    if !["lib", "main", "mod"].contains(&stem) {
        parts.push(stem.to_owned());
    }
    parts
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("a readable folder") {
        let path = entry.expect("an entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The code lines of `text` (trimmed; comment lines and trailing comments dropped), each
/// with the inline modules it sits in (`mod tests { use super::*; }`: `["tests"]`, whose
/// `super` is the file's own module).
fn code_lines(text: &str) -> Vec<(Vec<String>, &str)> {
    let mut out = Vec::new();
    // Inline modules open at a brace depth: (name, depth inside).
    let mut inline: Vec<(String, i32)> = Vec::new();
    let mut depth = 0;
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with("//") {
            continue;
        }
        let code = line.split("//").next().unwrap_or(line).trim_end();
        let declaration = code
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub ")
            .strip_prefix("mod ")
            .and_then(|rest| rest.strip_suffix('{'))
            .map(str::trim);
        if let Some(name) = declaration {
            inline.push((name.to_owned(), depth + 1));
        }
        out.push((inline.iter().map(|(name, _)| name.clone()).collect(), code));
        depth += code.matches('{').count() as i32 - code.matches('}').count() as i32;
        while inline.last().is_some_and(|(_, d)| *d > depth) {
            inline.pop();
        }
    }
    out
}

/// The start of a `use` line, if `code` is one.
fn use_start(code: &str) -> Option<&str> {
    ["pub use ", "pub(crate) use ", "pub(super) use ", "use "]
        .iter()
        .find_map(|p| code.strip_prefix(p))
}

/// The `use` statements of `text`, each without `use` and `;`, joined over their lines and
/// with the inline modules they sit in.
fn use_statements(text: &str) -> Vec<(Vec<String>, String)> {
    let mut statements = Vec::new();
    let mut current: Option<String> = None;
    for (within, code) in code_lines(text) {
        if let Some(open) = current.as_mut() {
            open.push(' ');
            open.push_str(code);
        } else if let Some(rest) = use_start(code) {
            current = Some(rest.to_owned());
        }
        if current.as_ref().is_some_and(|s| s.ends_with(';')) {
            let statement = current.take().unwrap_or_default();
            statements.push((within, statement.trim_end_matches(';').to_owned()));
        }
    }
    statements
}

/// Paths written in code outside `use` lines (`super::diagram_ui::diagram_ui(ui)`,
/// `crate::numbers::short(x)`), with the inline modules they sit in; comments and doc
/// comments (intra-doc links) are no imports.
fn inline_paths(text: &str) -> Vec<(Vec<String>, String)> {
    let mut out = Vec::new();
    for (within, code) in code_lines(text) {
        if use_start(code).is_some() {
            continue;
        }
        for start in ["crate::", "super::"] {
            for (at, _) in code.match_indices(start) {
                // A whole path: not the end of `my_crate::` nor the second `super` of
                // `super::super::x`.
                let before = code[..at].chars().next_back();
                if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                    continue;
                }
                let path: String = code[at..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                    .collect();
                out.push((within.clone(), path.trim_end_matches(':').to_owned()));
            }
        }
    }
    out
}

/// `statement` without its renames (`a::{b as c, d}` → `a::{b,d}`) and white space.
fn strip_renames(statement: &str) -> String {
    let tokens: Vec<&str> = statement.split_whitespace().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < tokens.len() {
        if tokens[i] == "as" && i + 1 < tokens.len() {
            // The new name goes; what closes the item (`,` `}`) stays.
            let closing: String = tokens[i + 1]
                .chars()
                .skip_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            out.push_str(&closing);
            i += 2;
        } else {
            out.push_str(tokens[i]);
            i += 1;
        }
    }
    out
}

/// The paths a `use` statement names, its braces expanded (`a::{b, c::d}` → `a::b`, `a::c::d`).
fn expand(statement: &str) -> Vec<String> {
    let statement = strip_renames(statement);
    let Some(open) = statement.find('{') else {
        return vec![statement];
    };
    let prefix = &statement[..open];
    let inner = &statement[open + 1..statement.rfind('}').unwrap_or(statement.len())];
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .filter(|p| !p.is_empty())
        .flat_map(|p| expand(&format!("{prefix}{p}")))
        .collect()
}

impl Crate {
    fn read(src: &Path) -> Self {
        let mut files = Vec::new();
        rust_files(src, &mut files);
        let modules = files
            .into_iter()
            .map(|f| (module_path(src, &f), f))
            .collect();
        Self { modules }
    }

    /// The file a path used from the module `from` resolves to (its longest module prefix),
    /// `None` outside the crate.
    fn resolve(&self, from: &[String], path: &str) -> Option<&PathBuf> {
        let mut segments: Vec<String> = Vec::new();
        let mut words = path.split("::").map(str::to_owned);
        let first = words.next()?;
        match first.as_str() {
            "crate" => {}
            "self" => segments.extend_from_slice(from),
            "super" => {
                segments.extend_from_slice(&from[..from.len().saturating_sub(1)]);
            }
            // A bare path names a child module of this one (`use rebuild::TableBuild;` in a
            // `mod.rs`), or an outside crate (`std::…`, `egui::…`).
            child => {
                let mut own: Vec<String> = from.to_vec();
                own.push(child.to_owned());
                if !self.modules.contains_key(&own) {
                    return None;
                }
                segments = own;
                for word in words {
                    segments.push(word);
                }
                return (0..=segments.len())
                    .rev()
                    .find_map(|k| self.modules.get(&segments[..k]));
            }
        }
        for word in words {
            if word == "super" {
                segments.pop();
            } else {
                segments.push(word);
            }
        }
        (0..=segments.len())
            .rev()
            .find_map(|k| self.modules.get(&segments[..k]))
    }

    /// Whether `file` is a module inside `module` (a facade's re-export of its own children
    /// is how a module shows its API, not an import).
    fn is_descendant(&self, file: &Path, module: &[String]) -> bool {
        self.modules
            .iter()
            .any(|(path, f)| f == file && path.len() > module.len() && path.starts_with(module))
    }

    /// Every file's imports of other files of the crate (a module's own descendants aside).
    fn edges(&self) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
        let mut edges = BTreeMap::new();
        for (module, file) in &self.modules {
            let text = std::fs::read_to_string(file).expect("a readable file");
            let mut paths: Vec<(Vec<String>, String)> = use_statements(&text)
                .into_iter()
                .flat_map(|(within, statement)| {
                    expand(&statement)
                        .into_iter()
                        .map(move |p| (within.clone(), p))
                })
                .collect();
            paths.extend(inline_paths(&text));
            let targets: BTreeSet<PathBuf> = paths
                .iter()
                .filter_map(|(within, p)| {
                    let from: Vec<String> = module.iter().chain(within).cloned().collect();
                    self.resolve(&from, p).cloned()
                })
                .filter(|t| t != file && !self.is_descendant(t, module))
                .collect();
            edges.insert(file.clone(), targets);
        }
        edges
    }
}

/// The strongly connected components of `edges` with more than one file (Tarjan).
fn circles(edges: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Vec<Vec<PathBuf>> {
    struct State<'a> {
        edges: &'a BTreeMap<PathBuf, BTreeSet<PathBuf>>,
        index: BTreeMap<&'a PathBuf, usize>,
        low: BTreeMap<&'a PathBuf, usize>,
        stack: Vec<&'a PathBuf>,
        on_stack: BTreeSet<&'a PathBuf>,
        next: usize,
        found: Vec<Vec<PathBuf>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a PathBuf) {
        s.index.insert(v, s.next);
        s.low.insert(v, s.next);
        s.next += 1;
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in s.edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.low[w].min(s.low[v]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w) {
                let low = s.index[w].min(s.low[v]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.push(w.clone());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                s.found.push(component);
            }
        }
    }
    let mut state = State {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        next: 0,
        found: Vec::new(),
    };
    for v in edges.keys() {
        if !state.index.contains_key(v) {
            visit(&mut state, v);
        }
    }
    state.found
}

#[test]
fn no_source_file_is_in_an_import_circle() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut found = Vec::new();
    for krate in ["core", "app"] {
        let src = root.join("crates").join(krate).join("src");
        let parsed = Crate::read(&src);
        assert!(
            parsed.modules.len() > 20,
            "{krate}: {} files",
            parsed.modules.len()
        );
        let edges = parsed.edges();
        let name = |f: &PathBuf| f.strip_prefix(root).unwrap_or(f).display().to_string();
        for circle in circles(&edges) {
            // Each file of the circle with the files of the circle it imports from.
            let imports: Vec<String> = circle
                .iter()
                .map(|f| {
                    let within: Vec<String> = edges[f]
                        .iter()
                        .filter(|t| circle.contains(t))
                        .map(name)
                        .collect();
                    format!("  {} imports {}", name(f), within.join(", "))
                })
                .collect();
            found.push(format!(
                "{}\n{}",
                circle.iter().map(name).collect::<Vec<_>>().join(" ↔ "),
                imports.join("\n")
            ));
        }
    }
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
}

#[test]
fn the_checker_finds_a_circle_it_is_shown() {
    // Two files importing from each other, and a parent re-exporting a child that imports
    // from the parent; a chain without a way back is no circle.
    let a = PathBuf::from("a.rs");
    let b = PathBuf::from("b.rs");
    let c = PathBuf::from("c.rs");
    let edges: BTreeMap<PathBuf, BTreeSet<PathBuf>> = [
        (a.clone(), BTreeSet::from([b.clone()])),
        (b.clone(), BTreeSet::from([a.clone(), c.clone()])),
        (c.clone(), BTreeSet::new()),
    ]
    .into();
    assert_eq!(circles(&edges), vec![vec![a.clone(), b.clone()]]);
    assert_eq!(
        expand("crate::x::{y, z::{w, v as u}, class}"),
        [
            "crate::x::y",
            "crate::x::z::w",
            "crate::x::z::v",
            "crate::x::class"
        ]
    );
    let statements = use_statements(
        "use crate::a;\nmod tests {\n    use super::*;\n}\nuse crate::{b,\n    c};\n",
    );
    assert_eq!(
        statements,
        [
            (vec![], "crate::a".to_owned()),
            (vec!["tests".to_owned()], "super::*".to_owned()),
            (vec![], "crate::{b, c}".to_owned()),
        ]
    );
    let krate = Crate {
        modules: [
            (vec![], PathBuf::from("lib.rs")),
            (vec!["app".to_owned()], PathBuf::from("app/mod.rs")),
            (
                vec!["app".to_owned(), "state".to_owned()],
                PathBuf::from("app/state.rs"),
            ),
        ]
        .into(),
    };
    let from = ["app".to_owned(), "state".to_owned()];
    assert_eq!(
        krate.resolve(&from, "super::Thing"),
        Some(&PathBuf::from("app/mod.rs"))
    );
    assert_eq!(
        krate.resolve(&from, "crate::app::state::X"),
        Some(&PathBuf::from("app/state.rs"))
    );
    assert_eq!(krate.resolve(&from, "std::fmt"), None);
}
