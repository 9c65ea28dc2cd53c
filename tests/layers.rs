//! The library's modules form layers: no module imports one that depends on it (issue 23),
//! and inside every folder of `src/` no file imports one that depends on it (issue 39).
//! Read from the sources, so a new import that closes a cycle fails here, naming the files.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The top-level module a file of `src/` belongs to (`None` for the crate root, the binary
/// and its command line, which sit above every module).
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel.components().next()?.as_os_str().to_str()?;
    let name = first.trim_end_matches(".rs");
    (!matches!(name, "lib" | "main" | "cli")).then(|| name.to_string())
}

/// The code of a file without comments and without its unit tests.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]\nmod tests").next().unwrap_or(text);
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Identifiers that follow `crate::` in `code`, and the first segments of a `crate::{...}`
/// group (nested groups included: `crate::{a::{X, Y}, b}` is `a` and `b`).
fn crate_paths(code: &str) -> Vec<String> {
    let ident = |s: &str| -> String {
        s.trim_start()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = Vec::new();
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + "crate::".len()..];
        let Some(group) = rest.strip_prefix('{') else {
            out.push(ident(rest));
            continue;
        };
        // Split the group at its top-level commas; each part's first identifier is a module
        // (or a root re-export).
        let (mut depth, mut start) = (0usize, 0usize);
        for (k, c) in group.char_indices() {
            match c {
                '{' => depth += 1,
                '}' if depth == 0 => {
                    out.push(ident(&group[start..k]));
                    break;
                }
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    out.push(ident(&group[start..k]));
                    start = k + 1;
                }
                _ => {}
            }
        }
    }
    out
}

/// Names the crate root re-exports, with the module each comes from.
fn root_reexports(lib: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for stmt in lib.split(';') {
        let Some(rest) = stmt.trim().strip_prefix("pub use ") else {
            continue;
        };
        let module: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let names = rest.rsplit("::").next().unwrap_or("");
        for n in names
            .split([',', '{', '}', ' ', '\n'])
            .filter(|n| !n.is_empty())
        {
            out.insert(n.to_string(), module.clone());
        }
    }
    out
}

#[test]
fn a_nested_import_group_names_each_module() {
    let got =
        crate_paths("use crate::{mesh::{Mesh, Mark}, solve::Warp, Error};\nx = crate::io::f();");
    assert_eq!(got, ["mesh", "solve", "Error", "io"]);
}

#[test]
fn no_module_imports_one_that_depends_on_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    let reexports = root_reexports(&code(&lib));
    assert!(reexports.contains_key("Retargeter"), "{reexports:?}");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let modules: BTreeSet<String> = files.iter().filter_map(|f| module_of(&src, f)).collect();
    // module -> module it imports -> files that do
    let mut edges: BTreeMap<String, BTreeMap<String, BTreeSet<String>>> = BTreeMap::new();
    for f in &files {
        let Some(from) = module_of(&src, f) else {
            continue;
        };
        let text = code(&std::fs::read_to_string(f).unwrap());
        for name in crate_paths(&text) {
            let to = if modules.contains(&name) {
                name
            } else if let Some(m) = reexports.get(&name) {
                m.clone()
            } else {
                continue;
            };
            if to != from {
                let rel = f.strip_prefix(&src).unwrap().display().to_string();
                edges
                    .entry(from.clone())
                    .or_default()
                    .entry(to)
                    .or_default()
                    .insert(rel);
            }
        }
    }
    assert!(
        edges
            .get("retarget")
            .is_some_and(|e| e.contains_key("mesh")),
        "the reader found the core's imports: {edges:?}"
    );
    // A cycle is a path back to where it started: depth-first from every module.
    for start in &modules {
        let mut stack = vec![(start.clone(), vec![start.clone()])];
        let mut seen = BTreeSet::new();
        while let Some((m, path)) = stack.pop() {
            for (next, why) in edges.get(&m).into_iter().flatten() {
                if next == start {
                    let files: Vec<_> = path
                        .windows(2)
                        .map(|w| format!("{} -> {}: {:?}", w[0], w[1], edges[&w[0]][&w[1]]))
                        .chain([format!("{m} -> {next}: {why:?}")])
                        .collect();
                    panic!("import cycle through {start}:\n{}", files.join("\n"));
                }
                if seen.insert(next.clone()) {
                    let mut p = path.clone();
                    p.push(next.clone());
                    stack.push((next.clone(), p));
                }
            }
        }
    }
}

/// A module's path from the crate root (`["io", "open"]` for `src/io/open.rs`, `["io"]` for
/// `src/io/mod.rs`); `None` for a crate root (`lib.rs`, `main.rs`).
fn module_path(rel: &str) -> Option<Vec<String>> {
    let mut parts: Vec<String> = rel
        .trim_end_matches(".rs")
        .split('/')
        .map(String::from)
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    (parts != ["lib"] && parts != ["main"]).then_some(parts)
}

/// The paths `crate::`, `super::` and `self::` lead to in `code`, made absolute from
/// `module` (the file's own module path), groups expanded: in `cli/still.rs`,
/// `super::{args::Cli, usage}` is `cli::args::Cli` and `cli::usage`.
fn absolute_paths(code: &str, module: &[String]) -> Vec<Vec<String>> {
    let bytes = code.as_bytes();
    let mut out = Vec::new();
    for start in ["crate::", "super::", "self::"] {
        for (i, _) in code.match_indices(start) {
            let before = i.checked_sub(1).map(|k| bytes[k] as char);
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            for rel in expand(&code[i..]) {
                let mut abs: Vec<String> = Vec::new();
                let mut segs = rel.into_iter().peekable();
                match segs.peek().map(String::as_str) {
                    Some("crate") => {
                        segs.next();
                    }
                    Some("self") => {
                        segs.next();
                        abs.extend_from_slice(module);
                    }
                    _ => {
                        abs.extend_from_slice(module);
                        while segs.peek().is_some_and(|s| s == "super") {
                            segs.next();
                            abs.pop();
                        }
                    }
                }
                abs.extend(segs.filter(|s| s != "self"));
                out.push(abs);
            }
        }
    }
    out
}

/// The paths written at the start of `text`: `a::b::{c, d::{e, f}}` is `a::b::c`,
/// `a::b::d::e` and `a::b::d::f`.
fn expand(text: &str) -> Vec<Vec<String>> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut prefix = Vec::new();
    let mut rest = text.trim_start();
    loop {
        if let Some(group) = rest.strip_prefix('{') {
            // Split the group at its top-level commas, each part a path of its own.
            let (mut depth, mut start, mut out) = (0usize, 0usize, Vec::new());
            for (k, c) in group.char_indices() {
                let end = match c {
                    '{' => {
                        depth += 1;
                        false
                    }
                    '}' if depth == 0 => true,
                    '}' => {
                        depth -= 1;
                        false
                    }
                    ',' => depth == 0,
                    _ => false,
                };
                if end {
                    for tail in expand(&group[start..k]) {
                        let mut p: Vec<String> = prefix.clone();
                        p.extend(tail);
                        out.push(p);
                    }
                    start = k + 1;
                    if c == '}' {
                        break;
                    }
                }
            }
            return out;
        }
        let name = ident(rest);
        if name.is_empty() {
            return if prefix.is_empty() {
                vec![]
            } else {
                vec![prefix]
            };
        }
        rest = &rest[name.len()..];
        prefix.push(name);
        match rest.strip_prefix("::") {
            Some(r) => rest = r.trim_start(),
            None => return vec![prefix],
        }
    }
}

/// Import edges between the entries of every folder: for each folder (its module path), the
/// entry (a file, or a subfolder) that imports -> the entry it imports -> the files that do.
/// `files` maps a path under `src/` to its text. A name a folder's `mod.rs` re-exports
/// (`super::GifSource`) counts as an import of the file it comes from; other names of
/// `mod.rs` (or `lib.rs`) itself are the folder's table of contents, no entry.
type Edges = BTreeMap<Vec<String>, BTreeMap<String, BTreeMap<String, BTreeSet<String>>>>;

fn folder_edges(files: &BTreeMap<String, String>) -> Edges {
    let modules: BTreeMap<Vec<String>, &str> = files
        .iter()
        .filter_map(|(rel, text)| Some((module_path(rel)?, text.as_str())))
        .collect();
    // Entries of each folder, and what its mod.rs (lib.rs for the root) re-exports.
    let mut entries: BTreeMap<Vec<String>, BTreeSet<String>> = BTreeMap::new();
    for m in modules.keys() {
        for k in 0..m.len() {
            entries
                .entry(m[..k].to_vec())
                .or_default()
                .insert(m[k].clone());
        }
    }
    let reexports: BTreeMap<Vec<String>, BTreeMap<String, String>> = files
        .iter()
        .filter_map(|(rel, text)| {
            let folder = if rel == "lib.rs" {
                vec![]
            } else if rel.ends_with("/mod.rs") {
                module_path(rel)?
            } else {
                return None;
            };
            Some((folder, root_reexports(&code(text))))
        })
        .collect();
    let mut edges = Edges::new();
    for (rel, text) in files {
        let Some(from) = module_path(rel) else {
            continue;
        };
        for path in absolute_paths(&code(text), &from) {
            // The deepest folder both share is where the edge runs.
            let shared = from.iter().zip(&path).take_while(|(a, b)| a == b).count();
            if shared >= from.len() || shared >= path.len() {
                continue; // itself, or a folder it is in
            }
            let folder = from[..shared].to_vec();
            let names = &entries[&folder];
            let to = if names.contains(&path[shared]) {
                path[shared].clone()
            } else if let Some(m) = reexports.get(&folder).and_then(|r| r.get(&path[shared])) {
                m.clone()
            } else {
                continue; // an item of the folder's mod.rs (or lib.rs)
            };
            if to != from[shared] {
                edges
                    .entry(folder)
                    .or_default()
                    .entry(from[shared].clone())
                    .or_default()
                    .entry(to)
                    .or_default()
                    .insert(rel.clone());
            }
        }
    }
    edges
}

/// The first import cycle found among the entries of one folder, as lines naming the files.
fn folder_cycle(edges: &Edges) -> Option<String> {
    for (folder, graph) in edges {
        for start in graph.keys() {
            let mut stack = vec![vec![start.clone()]];
            let mut seen = BTreeSet::new();
            while let Some(path) = stack.pop() {
                let m = path.last().unwrap();
                for next in graph.get(m).into_iter().flat_map(|e| e.keys()) {
                    if next == start {
                        let mut cycle = path.clone();
                        cycle.push(next.clone());
                        let lines: Vec<_> = cycle
                            .windows(2)
                            .map(|w| format!("{} -> {}: {:?}", w[0], w[1], graph[&w[0]][&w[1]]))
                            .collect();
                        return Some(format!(
                            "import cycle in src/{}:\n{}",
                            folder.join("/"),
                            lines.join("\n")
                        ));
                    }
                    if seen.insert(next.clone()) {
                        let mut p = path.clone();
                        p.push(next.clone());
                        stack.push(p);
                    }
                }
            }
        }
    }
    None
}

fn files_of(entries: &[(&str, &str)]) -> BTreeMap<String, String> {
    entries
        .iter()
        .map(|(p, t)| (p.to_string(), t.to_string()))
        .collect()
}

#[test]
fn paths_are_read_as_the_compiler_resolves_them() {
    let module = vec!["cli".to_string(), "still".to_string()];
    let got = absolute_paths(
        "use super::{args::{Cli, MethodArg}, usage};\nlet x = crate::io::f();\nself::g();",
        &module,
    );
    let joined: Vec<String> = got.iter().map(|p| p.join("::")).collect();
    assert_eq!(
        joined,
        [
            "io::f",
            "cli::args::Cli",
            "cli::args::MethodArg",
            "cli::usage",
            "cli::still::g"
        ]
    );
}

#[test]
fn a_cycle_between_two_files_of_a_folder_is_found() {
    // The circle issue 39 found: compare.rs took write_output from still.rs, which took
    // still_with from compare.rs.
    let files = files_of(&[
        ("main.rs", "mod cli;"),
        ("cli/mod.rs", "mod compare; mod still; fn usage() {}"),
        (
            "cli/compare.rs",
            "use super::usage;\nfn f() { super::still::write_output(); }",
        ),
        ("cli/still.rs", "use super::{usage, compare::still_with};"),
    ]);
    let cycle = folder_cycle(&folder_edges(&files)).expect("a cycle");
    assert!(
        cycle.contains("src/cli") && cycle.contains("cli/still.rs"),
        "{cycle}"
    );
    // Through a name the folder's mod.rs re-exports, and one folder down.
    let files = files_of(&[
        ("lib.rs", "mod io;"),
        ("io/mod.rs", "mod a; mod b; mod c; pub use b::Thing;"),
        ("io/a.rs", "use super::Thing;"),
        ("io/b.rs", "use crate::io::c::f;"),
        ("io/c/mod.rs", "mod d;"),
        ("io/c/d.rs", "use crate::io::a::g;"),
    ]);
    let cycle = folder_cycle(&folder_edges(&files)).expect("a cycle");
    assert!(cycle.contains("io/c/d.rs"), "{cycle}");
    // Imports one way only, and of the folder's own mod.rs, are no cycle.
    let files = files_of(&[
        ("cli/mod.rs", "mod a; mod b; fn usage() { a::f(); b::g(); }"),
        ("cli/a.rs", "use super::{usage, b::g};"),
        ("cli/b.rs", "use super::usage;"),
    ]);
    assert_eq!(folder_cycle(&folder_edges(&files)), None);
}

#[test]
fn no_file_imports_one_that_depends_on_it_in_any_folder() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut paths = Vec::new();
    sources(&src, &mut paths);
    let files: BTreeMap<String, String> = paths
        .iter()
        .map(|p| {
            let rel = p
                .strip_prefix(&src)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            (rel, std::fs::read_to_string(p).unwrap())
        })
        .collect();
    let edges = folder_edges(&files);
    // The reader sees imports inside folders: the command line's still job uses its args.
    let cli = &edges[&vec!["cli".to_string()]];
    assert!(
        cli.get("still").is_some_and(|e| e.contains_key("args")),
        "{cli:?}"
    );
    assert!(edges.contains_key(&vec!["io".to_string()]), "{edges:?}");
    if let Some(cycle) = folder_cycle(&edges) {
        panic!("{cycle}");
    }
}
