//! The structure `docs/architecture.md` promises, checked on the source tree (issue 41):
//! msd-ident's root stays small, modules import a name from the module that defines it
//! (not through their crate root's re-exports), no import circle spans more than two
//! files of a crate, and no function runs over 120 lines.
//!
//! The sources are read as text: `use crate::…` and `super::…` paths, comments and
//! `#[cfg(test)]` modules at the end of a file left out. A crate's root re-exports are
//! its `lib.rs` lines `pub use module::{…};` of its own modules.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library crates and the workspace's other libraries.
const CRATES: [&str; 13] = [
    "crates/msd-ode/src",
    "crates/msd-signal/src",
    "crates/msd-opt/src",
    "crates/msd-uff/src",
    "crates/msd-files/src",
    "crates/msd-modal-core/src",
    "crates/msd-modal/src",
    "crates/msd-ident/src",
    "crates/msd-mc/src",
    "crates/msd-experiment/src",
    "crates/msd-py/src",
    "xtask/src",
    "tests/src",
];

/// The most names msd-ident's root may show (issue 41).
const MAX_IDENT_ROOT_NAMES: usize = 60;

/// The longest a function may be, from its `fn` line to its closing brace (issue 41).
const MAX_FUNCTION_LINES: usize = 120;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ sits in the workspace")
        .to_path_buf()
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("readable source folder") {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The code of a file without comments and without a trailing `#[cfg(test)]` module.
fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("a readable source file");
    // A test module written out at the end (`#[cfg(test)]` then `mod tests {`), not a
    // declaration of a test file (`mod fit_tests;`).
    let test_module = text.match_indices("#[cfg(test)]\nmod ").find(|(i, _)| {
        text[*i..]
            .lines()
            .nth(1)
            .is_some_and(|l| l.trim_end().ends_with('{'))
    });
    let text = match test_module {
        Some((i, _)) => &text[..i],
        None => &text[..],
    };
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The items of a brace list at its top level: `a, b::{c, d}, e` → three items.
fn top_level_items(list: &str) -> Vec<String> {
    let (mut items, mut depth, mut current) = (Vec::new(), 0, String::new());
    for ch in list.chars() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(std::mem::take(&mut current).trim().to_string());
                continue;
            }
            _ => {}
        }
        current.push(ch);
    }
    items.push(current.trim().to_string());
    items.retain(|i| !i.is_empty());
    items
}

/// The text between the brace at `open` and its match.
fn braced(text: &str, open: usize) -> &str {
    let mut depth = 0;
    for (i, ch) in text[open..].char_indices() {
        match ch {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return &text[open + 1..open + i];
                }
            }
            _ => {}
        }
    }
    &text[open + 1..]
}

/// The modules a crate root declares and the names its `pub use` lines re-export from
/// them.
fn root_reexports(lib: &str) -> (BTreeSet<String>, BTreeSet<String>) {
    let mut modules = BTreeSet::new();
    let mut names = BTreeSet::new();
    for line in lib.lines() {
        let l = line.trim();
        for prefix in ["pub mod ", "mod ", "pub(crate) mod "] {
            if let Some(rest) = l.strip_prefix(prefix).and_then(|r| r.strip_suffix(';')) {
                modules.insert(rest.to_string());
            }
        }
    }
    let mut rest = lib;
    while let Some(i) = rest.find("\npub use ") {
        let start = i + "\npub use ".len();
        let end = rest[start..].find(';').map_or(rest.len(), |e| start + e);
        let path = &rest[start..end];
        let head = path.split("::").next().unwrap_or("");
        if modules.contains(head) {
            let tail = &path[head.len() + 2..];
            let items = match tail.find('{') {
                Some(b) => top_level_items(braced(tail, b)),
                None => vec![tail.to_string()],
            };
            for item in items {
                let last = item.rsplit("::").next().unwrap_or("");
                if !last.contains(' ') && !last.contains('{') && last != "self" {
                    names.insert(last.to_string());
                }
            }
        }
        rest = &rest[end..];
    }
    (modules, names)
}

/// Every name a file reaches through `crate::NAME` where NAME is a root re-export.
fn imports_through_root(code: &str, reexported: &BTreeSet<String>) -> Vec<String> {
    let mut found = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let before = rest[..i].chars().next_back();
        let after = &rest[i + "crate::".len()..];
        rest = after;
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        if after.starts_with('{') {
            for item in top_level_items(braced(after, 0)) {
                let name = item.split(" as ").next().unwrap_or("").trim();
                if reexported.contains(name) {
                    found.push(name.to_string());
                }
            }
            continue;
        }
        let name: String = after
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if reexported.contains(&name) && !after[name.len()..].starts_with("::") {
            found.push(name);
        }
    }
    found
}

/// A file's module path inside its crate: `src/a/b.rs` and `src/a/b/mod.rs` → [a, b].
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).expect("under src");
    let mut parts: Vec<String> = rel
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("lib" | "main" | "mod")
    ) {
        parts.pop();
    }
    parts
}

/// The files (as module paths) that a file's `crate::` and `super::` paths reach.
fn file_imports(
    module: &[String],
    code: &str,
    files: &BTreeSet<Vec<String>>,
) -> BTreeSet<Vec<String>> {
    let mut out = BTreeSet::new();
    for (i, _) in code
        .match_indices("crate::")
        .chain(code.match_indices("super::"))
    {
        let before = code[..i].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        let path: Vec<&str> = code[i..]
            .split(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
            .next()
            .unwrap_or("")
            .split("::")
            .filter(|s| !s.is_empty())
            .collect();
        let mut base: Vec<String> = if path[0] == "crate" {
            Vec::new()
        } else {
            module.to_vec()
        };
        let mut segments = &path[1..];
        if path[0] == "super" {
            base.pop();
            while segments.first() == Some(&"super") {
                base.pop();
                segments = &segments[1..];
            }
        }
        base.extend(segments.iter().map(|s| s.to_string()));
        // The longest prefix that is a file of the crate, other than this file or an
        // ancestor module (whose declarations hold this one).
        for k in (1..=base.len()).rev() {
            let target = base[..k].to_vec();
            if files.contains(&target) {
                if target != module && !module.starts_with(&target) {
                    out.insert(target);
                }
                break;
            }
        }
    }
    out
}

/// The strongly connected components of a graph (Tarjan), larger than one node.
fn circles(graph: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>) -> Vec<Vec<Vec<String>>> {
    struct State<'a> {
        graph: &'a BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        index: BTreeMap<&'a Vec<String>, usize>,
        low: BTreeMap<&'a Vec<String>, usize>,
        stack: Vec<&'a Vec<String>>,
        next: usize,
        out: Vec<Vec<Vec<String>>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a Vec<String>) {
        s.index.insert(v, s.next);
        s.low.insert(v, s.next);
        s.next += 1;
        s.stack.push(v);
        for w in &s.graph[v] {
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(lw);
            } else if s.stack.contains(&w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                component.push(w.clone());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                s.out.push(component);
            }
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

/// Functions longer than `MAX_FUNCTION_LINES` in `text`: (name, first line, length). A
/// function runs from its `fn` line to the first line after it that closes a brace at
/// the `fn` line's indentation.
fn long_functions(text: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        let signature = ["pub fn ", "pub(crate) fn ", "pub(super) fn ", "fn "]
            .iter()
            .find_map(|p| trimmed.strip_prefix(p));
        let Some(rest) = signature else { continue };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        // A declaration without a body (in a trait) ends with `;` before any `{`.
        let Some(open) = (i..lines.len()).find(|&j| {
            let l = lines[j].trim_end();
            l.ends_with('{') || l.ends_with(';')
        }) else {
            continue;
        };
        if lines[open].trim_end().ends_with(';') {
            continue;
        }
        let close = (open + 1..lines.len()).find(|&j| {
            let l = lines[j];
            l.len() - l.trim_start().len() == indent && l.trim_start().starts_with('}')
        });
        let length = close.map_or(lines.len(), |c| c + 1) - i;
        if length > MAX_FUNCTION_LINES {
            out.push((name, i + 1, length));
        }
    }
    out
}

#[test]
fn no_function_runs_over_120_lines() {
    let root = workspace();
    let mut offences = Vec::new();
    for src in CRATES {
        for file in rust_files(&root.join(src)) {
            let text = std::fs::read_to_string(&file).expect("a readable source file");
            for (name, line, length) in long_functions(&text) {
                offences.push(format!("{}:{line}: {name}, {length} lines", file.display()));
            }
        }
    }
    assert!(
        offences.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines:\n{}",
        offences.join("\n")
    );
}

#[test]
fn msd_idents_root_shows_at_most_sixty_names() {
    let lib = std::fs::read_to_string(workspace().join("crates/msd-ident/src/lib.rs"))
        .expect("msd-ident's lib.rs");
    let public_modules = lib
        .lines()
        .filter(|l| l.trim_start().starts_with("pub mod "))
        .count();
    let mut names = 0;
    let mut rest = lib.as_str();
    while let Some(i) = rest.find("\npub use ") {
        let start = i + "\npub use ".len();
        let end = rest[start..].find(';').map_or(rest.len(), |e| start + e);
        let path = &rest[start..end];
        names += match path.find('{') {
            Some(b) => top_level_items(braced(path, b)).len(),
            None => 1,
        };
        rest = &rest[end..];
    }
    let total = public_modules + names;
    assert!(
        total <= MAX_IDENT_ROOT_NAMES,
        "msd-ident's root shows {total} names ({public_modules} modules, {names} re-exports): at most {MAX_IDENT_ROOT_NAMES}"
    );
}

#[test]
fn modules_import_names_from_the_module_that_defines_them() {
    let root = workspace();
    let mut offences = Vec::new();
    for src in CRATES {
        let src = root.join(src);
        let lib = std::fs::read_to_string(src.join("lib.rs")).expect("lib.rs");
        let (_, reexported) = root_reexports(&lib);
        for file in rust_files(&src) {
            if file.file_name().is_some_and(|n| n == "lib.rs") {
                continue;
            }
            for name in imports_through_root(&code(&file), &reexported) {
                offences.push(format!("{}: crate::{name}", file.display()));
            }
        }
    }
    assert!(
        offences.is_empty(),
        "imported through the crate root's re-exports, not from the defining module:\n{}",
        offences.join("\n")
    );
}

#[test]
fn no_import_circle_spans_more_than_two_files() {
    let root = workspace();
    let mut offences = Vec::new();
    for src in CRATES {
        let src = root.join(src);
        let files = rust_files(&src);
        let modules: BTreeSet<Vec<String>> = files.iter().map(|f| module_path(&src, f)).collect();
        let graph: BTreeMap<_, _> = files
            .iter()
            .map(|f| {
                let m = module_path(&src, f);
                let edges = file_imports(&m, &code(f), &modules);
                (m, edges)
            })
            .collect();
        for circle in circles(&graph) {
            if circle.len() > 2 {
                let names: Vec<String> = circle.iter().map(|m| m.join("::")).collect();
                offences.push(format!("{}: {}", src.display(), names.join(" → ")));
            }
        }
    }
    assert!(
        offences.is_empty(),
        "import circles of more than two files:\n{}",
        offences.join("\n")
    );
}

/// The checks see what they are meant to: a root import in a use list and inline, a
/// circle of three files.
#[test]
fn the_checks_find_what_they_look_for() {
    let names: BTreeSet<String> = ["Parameters", "Result"].map(String::from).into();
    let code =
        "use crate::{Parameters, data::DataSet};\nfn f() -> crate::Result<()> { crate::data::x() }";
    assert_eq!(imports_through_root(code, &names), ["Parameters", "Result"]);
    let (modules, reexported) = root_reexports(
        "mod a;\npub mod b;\npub use a::{X, y::Z};\npub use b::W;\npub use other::V;\n",
    );
    assert_eq!(modules.len(), 2);
    assert_eq!(reexported.into_iter().collect::<Vec<_>>(), ["W", "X", "Z"]);
    let node = |s: &str| vec![s.to_string()];
    let graph: BTreeMap<_, _> = [
        (node("a"), [node("b")].into()),
        (node("b"), [node("c")].into()),
        (node("c"), [node("a")].into()),
        (node("d"), BTreeSet::new()),
    ]
    .into();
    assert_eq!(
        circles(&graph).iter().map(Vec::len).collect::<Vec<_>>(),
        [3]
    );
    let files: BTreeSet<Vec<String>> = [node("a"), node("b"), vec!["a".into(), "c".into()]].into();
    let module = vec!["a".to_string(), "c".to_string()];
    let edges = file_imports(&module, "use super::super::b::X; use crate::a::Y;", &files);
    assert_eq!(edges, [node("b")].into());
    let body = "    x += 1;\n".repeat(MAX_FUNCTION_LINES);
    let long = format!("fn short() {{\n}}\n\npub fn long(x: &mut u8) {{\n{body}}}\n");
    assert_eq!(
        long_functions(&long),
        [("long".to_string(), 4, MAX_FUNCTION_LINES + 2)]
    );
}

/// The lock keeps pest below its stack guard, whose psm and stacker build C and an
/// archive writer into the first build (Cargo.toml says why, and what replaces it).
#[test]
fn the_lock_holds_no_stack_guard_build() {
    let lock = std::fs::read_to_string(workspace().join("Cargo.lock")).unwrap();
    for name in ["psm", "stacker", "pest_stack_guard"] {
        assert!(
            !lock.contains(&format!("name = \"{name}\"")),
            "Cargo.lock holds {name}: `cargo update` took pest past 2.9.2 (see Cargo.toml)"
        );
    }
}
