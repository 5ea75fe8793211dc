//! The crate's layers: no import cycle between the library's top-level modules, and no library
//! module importing the bench or the command line (docs/architecture.md, "Layers").
//!
//! Parses every file under `src/` (no build, no Vulkan): comments, strings and character literals
//! are skipped; a file's references are its `crate::` paths (including `use crate::{a, b::c}`
//! groups) and `super::` paths that climb to the crate root. A file belongs to the top-level
//! module of its first path component (`src/passes/shade.rs`: `passes`); `src/main.rs` and the
//! modules it declares (`src/cli/`) are the binary, `main`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Edges `(from, to)` between top-level modules that the check ignores. Empty: an entry here is
/// a cycle accepted on purpose and needs a reason beside it.
const ALLOWED_EDGES: &[(&str, &str)] = &[];

/// Modules no other library module may import.
const TOP_ONLY: &[&str] = &["bench", "main"];

/// Where an edge was seen: file and line.
type Evidence = BTreeMap<(String, String), Vec<(String, usize)>>;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Tok<'a> {
    Ident(&'a str),
    Punct(char),
}

/// Tokens of Rust source with their line: identifiers and single punctuation characters, with
/// comments (nested block comments too), string, byte-string, raw-string and char literals skipped.
fn tokens(src: &str) -> Vec<(Tok<'_>, usize)> {
    let b = src.as_bytes();
    let (mut i, mut line, mut out) = (0usize, 1usize, Vec::new());
    let count_lines = |s: &[u8]| s.iter().filter(|&&c| c == b'\n').count();
    while i < b.len() {
        let c = b[i];
        if c == b'\n' {
            line += 1;
            i += 1;
        } else if c.is_ascii_whitespace() {
            i += 1;
        } else if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i..].starts_with(b"/*") {
            let (start, mut depth) = (i, 0usize);
            while i < b.len() {
                if b[i..].starts_with(b"/*") {
                    depth += 1;
                    i += 2;
                } else if b[i..].starts_with(b"*/") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            line += count_lines(&b[start..i.min(b.len())]);
        } else if let Some(end) = raw_string_end(b, i) {
            line += count_lines(&b[i..end]);
            i = end;
        } else if c == b'"' || (c == b'b' && b.get(i + 1) == Some(&b'"')) {
            let start = i;
            i += if c == b'b' { 2 } else { 1 };
            while i < b.len() && b[i] != b'"' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            i += 1;
            line += count_lines(&b[start..i.min(b.len())]);
        } else if c == b'\'' {
            // A char literal ('x', '\n', '\u{1F600}') or a lifetime ('a).
            if b.get(i + 1) == Some(&b'\\') {
                i += 2;
                while i < b.len() && b[i] != b'\'' {
                    i += 1;
                }
                i += 1;
            } else if let Some(len) = src[i + 1..].chars().next().map(char::len_utf8) {
                if b.get(i + 1 + len) == Some(&b'\'') {
                    i += 2 + len;
                } else {
                    i += 1; // a lifetime: its name follows as an identifier
                }
            } else {
                i += 1;
            }
        } else if c.is_ascii_alphabetic() || c == b'_' || c >= 0x80 {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_' || b[i] >= 0x80) {
                i += 1;
            }
            out.push((Tok::Ident(&src[start..i]), line));
        } else if c.is_ascii_digit() {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
        } else {
            out.push((Tok::Punct(c as char), line));
            i += 1;
        }
    }
    out
}

/// The end of a raw (byte) string starting at `i` (`r"..."`, `r#"..."#`, `br#"..."#`), if one does.
fn raw_string_end(b: &[u8], i: usize) -> Option<usize> {
    if i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_') {
        return None;
    }
    let mut j = i;
    if b.get(j) == Some(&b'b') {
        j += 1;
    }
    if b.get(j) != Some(&b'r') {
        return None;
    }
    j += 1;
    let hashes = b[j..].iter().take_while(|&&c| c == b'#').count();
    j += hashes;
    if b.get(j) != Some(&b'"') {
        return None;
    }
    j += 1;
    while j < b.len() {
        if b[j] == b'"'
            && b[j + 1..]
                .iter()
                .take(hashes)
                .filter(|&&c| c == b'#')
                .count()
                == hashes
        {
            return Some(j + 1 + hashes);
        }
        j += 1;
    }
    Some(b.len())
}

/// The first segments reached from `toks[i]` (just after a `::`): an identifier, or each item's
/// first identifier of a `{a, b::c, ...}` group.
fn first_segments<'a>(toks: &[(Tok<'a>, usize)], i: usize) -> Vec<&'a str> {
    match toks.get(i) {
        Some((Tok::Ident(s), _)) => vec![*s],
        Some((Tok::Punct('{'), _)) => {
            let (mut out, mut depth, mut expect) = (Vec::new(), 0usize, true);
            for (t, _) in &toks[i..] {
                match t {
                    Tok::Punct('{') => {
                        depth += 1;
                        if depth > 1 {
                            expect = false;
                        }
                    }
                    Tok::Punct('}') => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    Tok::Punct(',') if depth == 1 => expect = true,
                    Tok::Ident(s) if depth == 1 && expect => {
                        out.push(*s);
                        expect = false;
                    }
                    _ => {}
                }
            }
            out
        }
        _ => Vec::new(),
    }
}

fn is_sep(toks: &[(Tok<'_>, usize)], i: usize) -> bool {
    matches!(toks.get(i), Some((Tok::Punct(':'), _)))
        && matches!(toks.get(i + 1), Some((Tok::Punct(':'), _)))
}

/// The top-level modules `src` refers to, with the line of each reference. `module_path` is the
/// file's module path (`src/passes/shade.rs`: `["passes", "shade"]`; `src/scene.rs`: `["scene"]`),
/// which `super::` climbs from.
fn references(src: &str, module_path: &[&str]) -> Vec<(String, usize)> {
    let toks = tokens(src);
    let mut out = Vec::new();
    let mut i = 0;
    while i < toks.len() {
        // Skip the tail of a path (`a::crate` cannot occur; `x::super` neither).
        let after_sep = i >= 2 && is_sep(&toks, i - 2);
        match toks[i].0 {
            Tok::Ident("crate") if !after_sep && is_sep(&toks, i + 1) => {
                for s in first_segments(&toks, i + 3) {
                    out.push((s.to_string(), toks[i].1));
                }
                i += 3;
            }
            Tok::Ident("super") if !after_sep => {
                let mut depth = module_path.len();
                let mut j = i;
                while matches!(toks.get(j), Some((Tok::Ident("super"), _))) && is_sep(&toks, j + 1)
                {
                    depth = depth.saturating_sub(1);
                    j += 3;
                }
                if j > i {
                    if depth == 0 {
                        for s in first_segments(&toks, j) {
                            out.push((s.to_string(), toks[i].1));
                        }
                    }
                    i = j;
                } else {
                    i += 1;
                }
            }
            _ => i += 1,
        }
    }
    out
}

/// Paths into the library's internals in a client of the crate (the binary, the examples):
/// `vgeo::m::...` (also in `use vgeo::{m::x, ...}` groups) where `m` is one of `modules`, with
/// its line. The crate root's items (`vgeo::Renderer`, `vgeo::vk`) are the facade.
fn internal_paths(src: &str, modules: &BTreeSet<String>) -> Vec<(String, usize)> {
    let toks = tokens(src);
    let mut out = Vec::new();
    for i in 0..toks.len() {
        let after_sep = i >= 2 && is_sep(&toks, i - 2);
        if toks[i].0 == Tok::Ident("vgeo") && !after_sep && is_sep(&toks, i + 1) {
            for s in first_segments(&toks, i + 3) {
                // A group's item is a module only when a path follows it; `vgeo::x` alone is an
                // item of the root. first_segments gives names, so check what follows each.
                if modules.contains(s) && segment_continues(&toks, i + 3, s) {
                    out.push((s.to_string(), toks[i].1));
                }
            }
        }
    }
    out
}

/// Whether `name`, reached from `toks[i]` (an identifier or a `{...}` group), is followed by `::`.
fn segment_continues(toks: &[(Tok<'_>, usize)], i: usize, name: &str) -> bool {
    let end = match toks.get(i) {
        Some((Tok::Punct('{'), _)) => {
            let mut depth = 0usize;
            let mut j = i;
            while j < toks.len() {
                match toks[j].0 {
                    Tok::Punct('{') => depth += 1,
                    Tok::Punct('}') => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    _ => {}
                }
                j += 1;
            }
            j
        }
        _ => i + 1,
    };
    (i..end.min(toks.len())).any(|j| toks[j].0 == Tok::Ident(name) && is_sep(toks, j + 1))
}

/// The strongly connected components of more than one node (or a node with an edge to itself):
/// the import cycles (Tarjan).
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'g> {
        graph: &'g BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'g str, usize>,
        low: BTreeMap<&'g str, usize>,
        stack: Vec<&'g str>,
        on_stack: BTreeSet<&'g str>,
        out: Vec<Vec<String>>,
    }
    fn visit<'g>(s: &mut State<'g>, v: &'g str) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        let graph = s.graph;
        for w in graph.get(v).into_iter().flatten() {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.on_stack.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            let self_loop = graph.get(v).is_some_and(|e| e.contains(v));
            if comp.len() > 1 || self_loop {
                comp.sort();
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    let nodes: BTreeSet<&str> = graph
        .iter()
        .flat_map(|(k, v)| std::iter::once(k.as_str()).chain(v.iter().map(String::as_str)))
        .collect();
    for v in nodes {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The modules `mod NAME;` declares in `src` (with or without `pub`).
fn declared_modules(src: &str) -> BTreeSet<String> {
    let toks = tokens(src);
    let mut out = BTreeSet::new();
    for w in toks.windows(3) {
        if let [
            (Tok::Ident("mod"), _),
            (Tok::Ident(name), _),
            (Tok::Punct(';' | '{'), _),
        ] = w
        {
            out.insert(name.to_string());
        }
    }
    out
}

/// The graph of the crate's top-level modules (`main`: the binary), and where each edge is seen.
fn crate_graph(src_dir: &Path) -> (BTreeMap<String, BTreeSet<String>>, Evidence) {
    let read = |p: &Path| std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{p:?}: {e}"));
    let library = declared_modules(&read(&src_dir.join("lib.rs")));
    let binary = declared_modules(&read(&src_dir.join("main.rs")));
    assert!(library.contains("bench"), "lib.rs declares {library:?}");
    let mut files = Vec::new();
    rust_files(src_dir, &mut files);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut evidence = Evidence::new();
    for f in &files {
        let rel = f.strip_prefix(src_dir).unwrap();
        let mut parts: Vec<String> = rel
            .iter()
            .map(|c| c.to_string_lossy().into_owned())
            .collect();
        let last = parts.pop().unwrap();
        let stem = last.trim_end_matches(".rs").to_string();
        if stem != "mod" {
            parts.push(stem);
        }
        let (from, module_path): (String, Vec<&str>) = match parts.first().map(String::as_str) {
            Some("lib") if parts.len() == 1 => continue, // the root: declarations only
            Some("main") if parts.len() == 1 => ("main".into(), vec![]),
            Some(m) if binary.contains(m) => {
                ("main".into(), parts.iter().map(|s| s.as_str()).collect())
            }
            Some(m) if library.contains(m) => {
                (m.to_string(), parts.iter().map(|s| s.as_str()).collect())
            }
            _ => panic!(
                "{}: not under a module that lib.rs or main.rs declares",
                rel.display()
            ),
        };
        for (to, line) in references(&read(f), &module_path) {
            if to == from || to == "self" || to == "super" {
                continue;
            }
            graph.entry(from.clone()).or_default().insert(to.clone());
            evidence
                .entry((from.clone(), to))
                .or_default()
                .push((format!("src/{}", rel.display()), line));
        }
    }
    (graph, evidence)
}

/// The problems of `graph`: cycles (with the edges inside them and where they are seen) and
/// imports of a [`TOP_ONLY`] module.
fn problems(graph: &BTreeMap<String, BTreeSet<String>>, evidence: &Evidence) -> Vec<String> {
    let mut g = graph.clone();
    for (a, b) in ALLOWED_EDGES {
        if let Some(e) = g.get_mut(*a) {
            e.remove(*b);
        }
    }
    let mut out = Vec::new();
    let seen = |a: &str, b: &str| {
        evidence
            .get(&(a.to_string(), b.to_string()))
            .map(|v| {
                v.iter()
                    .take(3)
                    .map(|(f, l)| format!("{f}:{l}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            })
            .unwrap_or_default()
    };
    for comp in cycles(&g) {
        let mut msg = format!("import cycle between {comp:?}:");
        for a in &comp {
            for b in g.get(a).into_iter().flatten().filter(|b| comp.contains(b)) {
                msg.push_str(&format!("\n    {a} -> {b} ({})", seen(a, b)));
            }
        }
        out.push(msg);
    }
    for (from, tos) in &g {
        for to in tos.iter().filter(|t| TOP_ONLY.contains(&t.as_str())) {
            if from != "main" {
                out.push(format!(
                    "{from} imports {to} ({}): only the binary may",
                    seen(from, to)
                ));
            }
        }
    }
    out
}

fn graph_of(edges: &[(&str, &str)]) -> BTreeMap<String, BTreeSet<String>> {
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (a, b) in edges {
        g.entry(a.to_string()).or_default().insert(b.to_string());
    }
    g
}

#[test]
fn library_has_no_import_cycles_and_nothing_imports_bench_or_cli() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let (graph, evidence) = crate_graph(&src);
    // The parse found the layers it should (a broken parser would find no edges and pass).
    for (a, b) in [
        ("frame", "passes"),
        ("passes", "gpu"),
        ("passes", "material"),
        ("bench", "frame"),
        ("scene", "mesh"),
    ] {
        let found = graph.get(a).is_some_and(|e| e.contains(b));
        assert!(found, "expected an edge {a} -> {b}; graph: {graph:#?}");
    }
    let problems = problems(&graph, &evidence);
    assert!(
        problems.is_empty(),
        "{}\n(graph: {graph:#?})",
        problems.join("\n")
    );
}

#[test]
fn the_binary_and_the_examples_use_only_the_crate_root() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &Path| std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{p:?}: {e}"));
    let mut library = declared_modules(&read(&root.join("src/lib.rs")));
    assert!(
        library.contains("frame") && library.contains("gpu"),
        "{library:?}"
    );
    // Part of the facade: the command line's workflows as functions.
    assert!(library.remove("tools"), "lib.rs declares {library:?}");
    // The bench is an application beside the binary (top layer: nothing in the library imports
    // it, so the binary's `vgeo bench` reaches it directly).
    assert!(library.remove("bench"), "lib.rs declares {library:?}");
    let binary = declared_modules(&read(&root.join("src/main.rs")));
    let mut files = vec![root.join("src/main.rs")];
    for m in &binary {
        for f in [format!("src/{m}.rs"), format!("src/{m}/mod.rs")] {
            if root.join(&f).exists() {
                files.push(root.join(f));
            }
        }
        if root.join("src").join(m).is_dir() {
            rust_files(&root.join("src").join(m), &mut files);
        }
    }
    rust_files(&root.join("examples"), &mut files);
    assert!(files.len() >= 3, "{files:?}");
    let mut bad = Vec::new();
    for f in &files {
        for (m, line) in internal_paths(&read(f), &library) {
            bad.push(format!("{}:{line}: vgeo::{m}::", f.display()));
        }
    }
    assert!(
        bad.is_empty(),
        "the binary and the examples reach into the library's internals instead of its \
         crate-root facade:\n{}",
        bad.join("\n")
    );
    // The check sees such paths (a broken parser would pass anything).
    let found = internal_paths(
        "use vgeo::{Renderer, frame::View}; fn f() { vgeo::gpu::Context::new(); vgeo::Frame::x(); }",
        &library,
    );
    assert_eq!(
        found,
        vec![("frame".to_string(), 1), ("gpu".to_string(), 1)]
    );
}

#[test]
fn cycle_finder_finds_cycles_and_only_cycles() {
    let g = graph_of(&[("a", "b"), ("b", "c"), ("c", "a"), ("d", "a"), ("c", "e")]);
    assert_eq!(cycles(&g), vec![vec!["a", "b", "c"]]);
    let dag = graph_of(&[("a", "b"), ("b", "c"), ("a", "c"), ("d", "a")]);
    assert!(cycles(&dag).is_empty());
    let two = graph_of(&[("a", "b"), ("b", "a"), ("c", "d"), ("d", "c"), ("b", "c")]);
    assert_eq!(cycles(&two).len(), 2);
    assert_eq!(cycles(&graph_of(&[("a", "a")])), vec![vec!["a"]]);
    // problems() reports a cycle and an import of the bench, naming where they are seen.
    let bad = graph_of(&[
        ("material", "passes"),
        ("passes", "material"),
        ("render", "bench"),
    ]);
    let mut ev = Evidence::new();
    ev.insert(
        ("passes".into(), "material".into()),
        vec![("src/passes/shade.rs".into(), 13)],
    );
    let p = problems(&bad, &ev);
    assert_eq!(p.len(), 2, "{p:?}");
    assert!(
        p[0].contains("passes -> material (src/passes/shade.rs:13)"),
        "{p:?}"
    );
    assert!(p[1].starts_with("render imports bench"), "{p:?}");
}

#[test]
fn references_read_paths_not_comments_or_strings() {
    let src = r##"
        use crate::{camera::Camera, gpu::{self, Buffer}, shared};
        use crate::passes::view::ViewGpu;
        // use crate::bench::nothing;
        /* crate::bench /* nested */ crate::bench */
        const S: &str = "crate::bench::x";
        const R: &str = r#"crate::bench "quoted" x"#;
        const C: char = '"';
        fn f<'a>(x: &'a u8) -> u32 { crate::render::max_axis_scale(); super::scene_gpu::X }
    "##;
    let refs: Vec<String> = references(src, &["frame"])
        .into_iter()
        .map(|r| r.0)
        .collect();
    assert_eq!(
        refs,
        ["camera", "gpu", "shared", "passes", "render", "scene_gpu"]
    );
    // `super::` climbs from the file's module: from passes/shade.rs it stays in `passes`.
    let refs = references(
        "use super::view::X; use super::super::gpu::Y;",
        &["passes", "shade"],
    );
    assert_eq!(refs, vec![("gpu".to_string(), 1)]);
    assert_eq!(
        declared_modules("pub mod a;\nmod b;\n#[cfg(test)]\nmod tests { }"),
        ["a", "b", "tests"].iter().map(|s| s.to_string()).collect()
    );
}
