//! Architecture checks on the source tree: no import circle between modules of `src/` (a
//! module never imports one that imports it back, directly or through others), and the
//! backends (`integrators::cpu`, `integrators::gpu`) never import each other or the session
//! and benchmarks above them (`render::session`, `bench`).
//!
//! Imports are read from the source text: every `crate::a::b` or `super::x` path (in `use`
//! items and inline), resolved to the longest module prefix that exists as a file. The crate
//! root (`lib.rs`, a facade of re-exports) and `main.rs` are not nodes.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, recursively.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read src") {
        let p = entry.expect("dir entry").path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The module path of a file under src/ (`gpu/render.rs` -> `gpu::render`, `gpu/mod.rs` ->
/// `gpu`); `None` for the crate root and binaries.
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).ok()?;
    let mut parts: Vec<String> = rel
        .iter()
        .map(|c| c.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop()?;
    let stem = last.trim_end_matches(".rs");
    if parts.is_empty() && (stem == "lib" || stem == "main") {
        return None;
    }
    if parts.first().is_some_and(|p| p == "bin") {
        return None;
    }
    if stem != "mod" {
        parts.push(stem.to_string());
    }
    Some(parts.join("::"))
}

/// Strips `//` comments (doc comments included) so paths in prose are not imports.
fn code_only(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Module paths this file refers to: `crate::x::y...` and `super::...`, plus the names in
/// `use crate::x::{a, b::c}` groups.
fn referenced_paths(module: &str, text: &str) -> Vec<Vec<String>> {
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = Vec::new();
    let code = code_only(text);
    let bytes: Vec<char> = code.chars().collect();
    let inline = inline_modules(&bytes);
    let mut i = 0;
    while i < bytes.len() {
        let rest: String = bytes[i..bytes.len().min(i + 7)].iter().collect();
        let (base, skip): (Vec<String>, usize) =
            if rest.starts_with("crate::") && (i == 0 || !ident(bytes[i - 1])) {
                (Vec::new(), 7)
            } else if rest.starts_with("super::") && (i == 0 || !ident(bytes[i - 1])) {
                let mut b: Vec<String> = module.split("::").map(String::from).collect();
                // A file's `super` is its parent module (for mod.rs files the module itself is
                // the directory, whose parent is one level up too); inside an inline module
                // (`mod tests { use super::*; }`) it is the file's own module.
                if !inline[i] {
                    b.pop();
                }
                (b, 7)
            } else {
                i += 1;
                continue;
            };
        i += skip;
        let mut segs = base.clone();
        loop {
            let start = i;
            while i < bytes.len() && ident(bytes[i]) {
                i += 1;
            }
            if i > start {
                segs.push(bytes[start..i].iter().collect());
            }
            if i + 1 < bytes.len() && bytes[i] == ':' && bytes[i + 1] == ':' {
                i += 2;
                if i < bytes.len() && bytes[i] == '{' {
                    // A group: each element extends the prefix.
                    let close = (i..bytes.len()).find(|&j| bytes[j] == '}').unwrap_or(i);
                    let group: String = bytes[i + 1..close].iter().collect();
                    for item in group.split(',') {
                        let mut p = segs.clone();
                        p.extend(
                            item.trim()
                                .split("::")
                                .map(|s| s.trim().to_string())
                                .filter(|s| !s.is_empty() && s.chars().all(ident)),
                        );
                        out.push(p);
                    }
                    i = close;
                    break;
                }
                continue;
            }
            break;
        }
        out.push(segs);
    }
    out
}

/// For each character of `code`, whether it lies inside an inline module (`mod name { .. }`).
fn inline_modules(code: &[char]) -> Vec<bool> {
    let text: String = code.iter().collect();
    let mut inside = vec![false; code.len()];
    let mut search = 0;
    while let Some(found) = text[search..].find("mod ") {
        // Char indices equal byte indices only for ASCII; map through char_indices.
        let at = search + found;
        search = at + 4;
        let rest = &text[search..];
        let name_len = rest
            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        let after = rest[name_len..].trim_start();
        if name_len == 0 || !after.starts_with('{') {
            continue;
        }
        let open = search + name_len + (rest[name_len..].len() - after.len());
        let mut depth = 0usize;
        let start = text[..open].chars().count();
        for (k, c) in text[open..].chars().enumerate() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                _ => {}
            }
            if start + k < inside.len() {
                inside[start + k] = true;
            }
            if depth == 0 {
                break;
            }
        }
    }
    inside
}

/// The longest prefix of `path` that names a module.
fn resolve(path: &[String], modules: &BTreeSet<String>) -> Option<String> {
    (1..=path.len())
        .rev()
        .map(|n| path[..n].join("::"))
        .find(|m| modules.contains(m))
}

fn import_graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mods: Vec<(String, PathBuf)> = files
        .iter()
        .filter_map(|f| module_of(&src, f).map(|m| (m, f.clone())))
        .collect();
    let names: BTreeSet<String> = mods.iter().map(|m| m.0.clone()).collect();
    let mut graph = BTreeMap::new();
    for (m, f) in &mods {
        let text = std::fs::read_to_string(f).expect("read source");
        let deps: BTreeSet<String> = referenced_paths(m, &text)
            .iter()
            .filter_map(|p| resolve(p, &names))
            .filter(|d| d != m)
            .collect();
        graph.insert(m.clone(), deps);
    }
    graph
}

/// A cycle through `start`, if any (depth-first search).
fn cycle_from(graph: &BTreeMap<String, BTreeSet<String>>, start: &str) -> Option<Vec<String>> {
    fn walk(
        g: &BTreeMap<String, BTreeSet<String>>,
        node: &str,
        start: &str,
        path: &mut Vec<String>,
        seen: &mut BTreeSet<String>,
    ) -> bool {
        for next in g.get(node).into_iter().flatten() {
            if next == start {
                return true;
            }
            if seen.insert(next.clone()) {
                path.push(next.clone());
                if walk(g, next, start, path, seen) {
                    return true;
                }
                path.pop();
            }
        }
        false
    }
    let mut path = vec![start.to_string()];
    let mut seen = BTreeSet::new();
    walk(graph, start, start, &mut path, &mut seen).then_some(path)
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let graph = import_graph();
    assert!(
        graph.contains_key("render::session") && graph.contains_key("integrators::cpu"),
        "{graph:?}"
    );
    let cycles: Vec<String> = graph
        .keys()
        .filter_map(|m| cycle_from(&graph, m))
        .map(|c| c.join(" -> "))
        .collect();
    assert!(cycles.is_empty(), "import circles:\n{}", cycles.join("\n"));
}

#[test]
fn the_backends_import_neither_each_other_nor_the_session() {
    let graph = import_graph();
    // The backend a module belongs to, or the part of the crate above them.
    let part = |m: &str| -> &'static str {
        let mut segs = m.split("::");
        match (segs.next(), segs.next()) {
            (Some("integrators"), Some("cpu")) => "cpu",
            (Some("integrators"), Some("gpu")) => "gpu",
            (Some("render"), Some("session")) | (Some("bench"), _) => "above",
            _ => "",
        }
    };
    for (m, deps) in &graph {
        let other = match part(m) {
            "cpu" => "gpu",
            "gpu" => "cpu",
            _ => continue,
        };
        let bad: Vec<&String> = deps
            .iter()
            .filter(|d| {
                let p = part(d);
                p == other || p == "above"
            })
            .collect();
        assert!(bad.is_empty(), "{m} imports {bad:?}");
    }
}

#[test]
fn the_circle_check_finds_a_circle() {
    // The checker itself must be able to fail: a two-module circle is found.
    let mut g = BTreeMap::new();
    g.insert("a".to_string(), BTreeSet::from(["b".to_string()]));
    g.insert("b".to_string(), BTreeSet::from(["a".to_string()]));
    assert_eq!(
        cycle_from(&g, "a"),
        Some(vec!["a".to_string(), "b".to_string()])
    );
    let names = BTreeSet::from(["gpu".to_string(), "gpu::render".to_string()]);
    let paths = referenced_paths("gpu::probe", "use super::render::{GpuRun, read_back};");
    assert_eq!(resolve(&paths[0], &names).as_deref(), Some("gpu::render"));
}
