//! The house: the workspace's file-level module graph has no circle, the output layer stands on
//! nothing above the error type, and the architecture page's picture of the floors is the one
//! the code gives.
//!
//! The graph's nodes are the source files of the five crates. File A depends on file B when A
//! names an item B defines: a `use` or a path (`crate::…`, `super::…`, `self::…`, or a child
//! module's name), resolved through `pub use` re-exports to the file that defines the item. A
//! `pub use` itself is name forwarding, not a dependency. A folder's face (`model.rs` or
//! `mod.rs`) and the files under it are one room: a file's use of its own ancestors' items
//! (`super::Model`) is how Rust folders share their vocabulary, and is not counted; the face's
//! use of its children is. And the equation of motion is hand-written only where a benchmark
//! keeps a specialised path.
//!
//! **Why one file.** Every check here reads the same source through the same comment-stripping
//! and file walk: the graph, its floors and the scan for a hand-written equation are one reading
//! of the code.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module's path inside its crate (`["model", "terms"]`; empty for the crate root).
type ModPath = Vec<String>;

/// The files under `dir`, at any depth.
pub fn files_under(dir: &Path) -> Vec<PathBuf> {
    let (mut files, mut stack) = (Vec::new(), vec![dir.to_path_buf()]);
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let path = e.path();
            if path.is_dir() {
                stack.push(path);
            } else {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// `text` without comments and with string literals emptied, so that neither a doc link nor a
/// message counts as a use.
fn code_of(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let b: Vec<char> = text.chars().collect();
    let mut i = 0;
    let mut depth = 0usize; // block-comment nesting
    while i < b.len() {
        let next = b.get(i + 1).copied();
        if depth > 0 {
            if b[i] == '*' && next == Some('/') {
                depth -= 1;
                i += 2;
            } else if b[i] == '/' && next == Some('*') {
                depth += 1;
                i += 2;
            } else {
                i += 1;
            }
        } else if b[i] == '/' && next == Some('*') {
            depth = 1;
            i += 2;
        } else if b[i] == '/' && next == Some('/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if b[i] == '"' {
            // a string literal (raw strings have no quote inside in this code base)
            out.push_str("\"\"");
            i += 1;
            while i < b.len() && b[i] != '"' {
                i += if b[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
        } else if b[i] == '\'' && next.is_some_and(|c| c != '\\') && b.get(i + 2) == Some(&'\'') {
            // a char literal such as '"' or '{'
            out.push_str("' '");
            i += 3;
        } else if b[i] == '\'' && next == Some('\\') {
            out.push_str("' '");
            i += 2;
            while i < b.len() && b[i] != '\'' {
                i += 1;
            }
            i += 1;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    out
}

/// The paths a use tree (`a::{b, c::{d, e as f}}`) names, each split at `::`.
fn use_paths(prefix: &[String], tree: &str, out: &mut Vec<Vec<String>>) {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let path = tree.split(" as ").next().unwrap_or("").trim();
        let mut p = prefix.to_vec();
        p.extend(path.split("::").filter(|s| !s.is_empty()).map(String::from));
        if !p.is_empty() {
            out.push(p);
        }
        return;
    };
    let mut head = prefix.to_vec();
    head.extend(
        tree[..open]
            .split("::")
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from),
    );
    let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
    let (mut depth, mut start) = (0i32, 0);
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                use_paths(&head, &inner[start..i], out);
                start = i + 1;
            }
            _ => {}
        }
    }
    if !inner[start..].trim().is_empty() {
        use_paths(&head, &inner[start..], out);
    }
}

/// A file's `use` statements, read once.
struct Uses {
    /// Each statement's tree, with whether it is `pub` (any visibility).
    statements: Vec<(bool, String)>,
    /// The code without its `pub use` statements (they forward names; they use nothing).
    plain: String,
}

/// The `use` statements of `code`. A statement is `pub` when the token just before `use` is
/// `pub` or `pub(…)`.
fn uses(code: &str) -> Uses {
    let (mut statements, mut plain) = (Vec::new(), String::with_capacity(code.len()));
    let mut rest = code;
    while let Some(at) = find_word(rest, "use") {
        let before = rest[..at].trim_end();
        let visibility = before.rsplit(char::is_whitespace).next().unwrap_or("");
        let public = visibility == "pub" || visibility.starts_with("pub(");
        let after = &rest[at + 3..];
        let end = after.find(';').unwrap_or(after.len());
        statements.push((public, after[..end].to_string()));
        plain.push_str(if public {
            &before[..before.len() - visibility.len()]
        } else {
            &rest[..at + 3 + end]
        });
        rest = &after[end..];
    }
    plain.push_str(rest);
    Uses { statements, plain }
}

/// The byte offset of `word` standing alone in `text`.
fn find_word(text: &str, word: &str) -> Option<usize> {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut from = 0;
    while let Some(i) = text[from..].find(word).map(|i| i + from) {
        let before = text[..i].chars().next_back();
        let after = text[i + word.len()..].chars().next();
        if !before.is_some_and(ident) && !after.is_some_and(ident) {
            return Some(i);
        }
        from = i + word.len();
    }
    None
}

/// Every `head::a::b…` path in `code` whose first segment is `head` standing alone.
fn paths_from(code: &str, head: &str) -> Vec<Vec<String>> {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = Vec::new();
    let pat = format!("{head}::");
    let mut from = 0;
    while let Some(i) = code[from..].find(&pat).map(|i| i + from) {
        from = i + pat.len();
        let before = code[..i].chars().next_back();
        if before.is_some_and(|c| ident(c) || c == ':') {
            continue;
        }
        let mut p = vec![head.to_string()];
        let mut rest = &code[from..];
        loop {
            let n = rest.find(|c: char| !ident(c)).unwrap_or(rest.len());
            if n == 0 {
                break;
            }
            p.push(rest[..n].to_string());
            rest = &rest[n..];
            match rest.strip_prefix("::") {
                Some(r) => rest = r,
                None => break,
            }
        }
        out.push(p);
    }
    out
}

/// One crate's file graph: each file's module path and the files it depends on.
pub struct Graph {
    /// The file of each module.
    pub files: BTreeMap<ModPath, PathBuf>,
    /// The modules each module depends on (see the module docs).
    pub edges: BTreeMap<ModPath, BTreeSet<ModPath>>,
}

/// The module path of `file` under `src`, whose root file is `root` (`lib.rs`, `main.rs`).
fn mod_path(src: &Path, file: &Path, root: &str) -> ModPath {
    let rel = file
        .strip_prefix(src)
        .unwrap()
        .to_string_lossy()
        .replace('\\', "/");
    if rel == root {
        return Vec::new();
    }
    let mut p: ModPath = rel
        .trim_end_matches(".rs")
        .split('/')
        .map(String::from)
        .collect();
    if p.last().is_some_and(|l| l == "mod") {
        p.pop();
    }
    p
}

impl Graph {
    /// The graph of the crate whose sources are `src`, rooted at `root`.
    pub fn of(src: &Path, root: &str) -> Graph {
        let files: BTreeMap<ModPath, PathBuf> = files_under(src)
            .into_iter()
            .filter(|f| f.extension().is_some_and(|e| e == "rs"))
            .map(|f| (mod_path(src, &f, root), f))
            .collect();
        let code: BTreeMap<ModPath, Uses> = files
            .iter()
            .map(|(m, f)| {
                (
                    m.clone(),
                    uses(&code_of(&std::fs::read_to_string(f).unwrap())),
                )
            })
            .collect();
        let mut g = Graph {
            files,
            edges: BTreeMap::new(),
        };
        // `pub use` re-exports: a name in a module → the path it forwards to
        let mut exports: BTreeMap<ModPath, BTreeMap<String, ModPath>> = BTreeMap::new();
        for (m, u) in &code {
            for (_, tree) in u.statements.iter().filter(|(public, _)| *public) {
                let mut paths = Vec::new();
                use_paths(&[], tree, &mut paths);
                for p in paths {
                    let (name, target) = match p.last().map(String::as_str) {
                        Some("self") => (p[p.len() - 2].clone(), p[..p.len() - 1].to_vec()),
                        Some("*") | None => continue,
                        Some(n) => (n.to_string(), p.clone()),
                    };
                    if let Some(t) = g.absolute(m, &target) {
                        exports.entry(m.clone()).or_default().insert(name, t);
                    }
                }
            }
        }
        for (m, u) in &code {
            let mut paths = Vec::new();
            for (_, tree) in u.statements.iter().filter(|(public, _)| !*public) {
                use_paths(&[], tree, &mut paths);
            }
            let plain = &u.plain;
            for head in ["crate", "super", "self"] {
                paths.extend(paths_from(plain, head));
            }
            for child in g
                .files
                .keys()
                .filter(|k| k.len() == m.len() + 1 && k.starts_with(m))
            {
                for mut p in paths_from(plain, child.last().unwrap()) {
                    p.insert(0, "self".into());
                    paths.push(p);
                }
            }
            for p in paths {
                let Some(abs) = g.absolute(m, &p) else {
                    continue;
                };
                let Some(target) = resolve(&g.files, &exports, &abs, 0) else {
                    continue;
                };
                // a file's use of its own ancestors' items is the folder's shared vocabulary
                if target != *m && !m.starts_with(&target) {
                    g.edges.entry(m.clone()).or_default().insert(target);
                }
            }
        }
        g
    }

    /// `p` (as written in module `m`) from the crate root, if it names a module of the crate.
    fn absolute(&self, m: &ModPath, p: &[String]) -> Option<ModPath> {
        let mut base = m.clone();
        let mut rest = p;
        match p.first().map(String::as_str) {
            Some("crate") => {
                base.clear();
                rest = &p[1..];
            }
            Some("super" | "self") => {
                while let Some(s) = rest.first() {
                    match s.as_str() {
                        "super" => {
                            base.pop();
                        }
                        "self" => {}
                        _ => break,
                    }
                    rest = &rest[1..];
                }
            }
            Some(first) => {
                let mut child = m.clone();
                child.push(first.to_string());
                if !self.files.contains_key(&child) {
                    return None;
                }
            }
            None => return None,
        }
        base.extend(rest.iter().cloned());
        Some(base)
    }

    /// The circles of the graph: its strongly connected components of two files or more.
    pub fn circles(&self) -> Vec<Vec<ModPath>> {
        let nodes: Vec<&ModPath> = self.files.keys().collect();
        let index: BTreeMap<&ModPath, usize> =
            nodes.iter().enumerate().map(|(i, m)| (*m, i)).collect();
        let adj: Vec<Vec<usize>> = nodes
            .iter()
            .map(|m| {
                self.edges
                    .get(*m)
                    .into_iter()
                    .flatten()
                    .filter_map(|t| index.get(t).copied())
                    .collect()
            })
            .collect();
        strongly_connected(&adj)
            .into_iter()
            .filter(|c| c.len() > 1)
            .map(|c| c.into_iter().map(|i| nodes[i].clone()).collect())
            .collect()
    }
}

/// The file defining the item at absolute path `p`: the longest prefix that is a module, then
/// through that module's re-export of the next name, if it has one.
fn resolve(
    files: &BTreeMap<ModPath, PathBuf>,
    exports: &BTreeMap<ModPath, BTreeMap<String, ModPath>>,
    p: &[String],
    depth: usize,
) -> Option<ModPath> {
    let k = (0..=p.len())
        .rev()
        .find(|&k| files.contains_key(&p[..k].to_vec()))?;
    let module = p[..k].to_vec();
    if let Some(name) = p.get(k)
        && depth < 16
        && let Some(target) = exports.get(&module).and_then(|e| e.get(name))
    {
        let mut forwarded = target.clone();
        forwarded.extend(p[k + 1..].iter().cloned());
        if let Some(r) = resolve(files, exports, &forwarded, depth + 1) {
            return Some(r);
        }
    }
    Some(module)
}

/// Tarjan's strongly connected components of the graph `adj` (iterative).
fn strongly_connected(adj: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let n = adj.len();
    let (mut index, mut low, mut on) = (vec![usize::MAX; n], vec![0; n], vec![false; n]);
    let (mut stack, mut out, mut next) = (Vec::new(), Vec::new(), 0);
    for root in 0..n {
        if index[root] != usize::MAX {
            continue;
        }
        let mut work = vec![(root, 0usize)];
        while let Some((v, i)) = work.pop() {
            if i == 0 {
                index[v] = next;
                low[v] = next;
                next += 1;
                stack.push(v);
                on[v] = true;
            }
            if let Some(&w) = adj[v].get(i) {
                work.push((v, i + 1));
                if index[w] == usize::MAX {
                    work.push((w, 0));
                } else if on[w] {
                    low[v] = low[v].min(index[w]);
                }
                continue;
            }
            if low[v] == index[v] {
                let mut comp = Vec::new();
                while let Some(w) = stack.pop() {
                    on[w] = false;
                    comp.push(w);
                    if w == v {
                        break;
                    }
                }
                out.push(comp);
            }
            if let Some(&(parent, _)) = work.last() {
                low[parent] = low[parent].min(low[v]);
            }
        }
    }
    out
}

/// The five crates' sources and root files.
fn crates() -> [(PathBuf, &'static str); 5] {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    [
        (here.join("src"), "lib.rs"),
        (here.join("../hdgear-cli/src"), "main.rs"),
        (here.join("../hdgear-py/src"), "lib.rs"),
        (here.join("../hdgear-fmu/src"), "lib.rs"),
        (here.join("../hdgear-record/src"), "lib.rs"),
    ]
}

#[test]
fn no_file_of_the_workspace_stands_in_a_circle() {
    for (src, root) in crates() {
        let g = Graph::of(&src, root);
        // the graph read the crate: every file at its top, and edges wherever there are more
        // than a root and one module (the FMU's crate is lib.rs and ffi.rs, the derive's lib.rs)
        let files = std::fs::read_dir(&src).unwrap().count();
        let edges: usize = g.edges.values().map(BTreeSet::len).sum();
        assert!(g.files.len() >= files, "{}", src.display());
        assert!(files <= 2 || edges > 10, "{}", src.display());
        let circles: Vec<String> = g
            .circles()
            .iter()
            .map(|c| {
                c.iter()
                    .map(|m| m.join("::"))
                    .collect::<Vec<_>>()
                    .join(" ⇄ ")
            })
            .collect();
        assert!(
            circles.is_empty(),
            "{}: circles {circles:#?}",
            src.display()
        );
    }
}

#[test]
fn the_graph_sees_a_circle_through_a_re_export_and_not_through_an_ancestor() {
    // a crate written here: `b` uses `a`'s item by its re-export in the root, and `a` uses `b`;
    // `a/inner` uses its ancestor `a`, which uses it back (one room, not a circle)
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path();
    std::fs::create_dir(src.join("a")).unwrap();
    std::fs::write(src.join("lib.rs"), "mod a;\nmod b;\npub use a::Thing;\n").unwrap();
    std::fs::write(src.join("a.rs"), "mod inner;\nuse crate::b::other;\n// crate::b::Ghost\nfn f() { inner::g(); }\npub struct Thing;\n").unwrap();
    std::fs::write(
        src.join("a/inner.rs"),
        "use super::Thing;\npub fn g() { let s = \"crate::b::Nope\"; }\n",
    )
    .unwrap();
    std::fs::write(src.join("b.rs"), "use crate::Thing;\npub fn other() {}\n").unwrap();
    let g = Graph::of(src, "lib.rs");
    let m = |s: &str| s.split("::").map(String::from).collect::<ModPath>();
    let circles: Vec<BTreeSet<ModPath>> = g
        .circles()
        .into_iter()
        .map(|c| c.into_iter().collect())
        .collect();
    assert_eq!(circles, [BTreeSet::from([m("a"), m("b")])]);
    assert_eq!(g.edges[&m("b")], BTreeSet::from([m("a")]));
    assert_eq!(g.edges[&m("a")], BTreeSet::from([m("a::inner"), m("b")]));
    assert!(!g.edges.contains_key(&m("a::inner")), "{:?}", g.edges);
}

/// The library's top-level modules and those each stands on (its files' edges, collapsed).
fn floors_graph() -> BTreeMap<String, BTreeSet<String>> {
    let (src, root) = &crates()[0];
    let g = Graph::of(src, root);
    let mut top: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for m in g.files.keys().filter(|m| !m.is_empty()) {
        top.entry(m[0].clone()).or_default();
    }
    for (m, targets) in &g.edges {
        for t in targets
            .iter()
            .filter(|t| !t.is_empty() && !m.is_empty() && t[0] != m[0])
        {
            top.entry(m[0].clone()).or_default().insert(t[0].clone());
        }
    }
    top
}

/// The picture of the floors: each top-level module on the floor one above the highest it
/// stands on, the top floor first, with what each module stands on directly.
fn floors_picture(graph: &BTreeMap<String, BTreeSet<String>>) -> String {
    let mut floor: BTreeMap<&str, usize> = BTreeMap::new();
    while floor.len() < graph.len() {
        let before = floor.len();
        for (m, deps) in graph {
            if !floor.contains_key(m.as_str())
                && deps.iter().all(|d| floor.contains_key(d.as_str()))
            {
                let f = deps
                    .iter()
                    .map(|d| floor[d.as_str()] + 1)
                    .max()
                    .unwrap_or(0);
                floor.insert(m, f);
            }
        }
        assert!(
            floor.len() > before,
            "the top-level modules stand in a circle: {graph:?}"
        );
    }
    let top = floor.values().copied().max().unwrap_or(0);
    let mut out = String::new();
    for f in (0..=top).rev() {
        out.push_str(&format!("floor {f}\n"));
        for (m, _) in floor.iter().filter(|(_, g)| **g == f) {
            let deps: Vec<&str> = graph[*m].iter().map(String::as_str).collect();
            let on = if deps.is_empty() {
                String::new()
            } else {
                format!(" → {}", deps.join(", "))
            };
            out.push_str(format!("  {m:<12}{on}").trim_end());
            out.push('\n');
        }
    }
    out
}

#[test]
fn output_is_the_bottom_layer() {
    // the I/O layer knows nothing above the error type
    let graph = floors_graph();
    assert_eq!(graph["output"], BTreeSet::from(["error".to_string()]));
}

/// The architecture page's picture of the floors is the code's: rewritten by
/// `HDGEAR_BLESS=1 cargo test --release -p hdgear --test tests -- house`.
#[test]
fn the_architecture_pages_floors_are_the_codes() {
    let page = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/src/architecture.md");
    let text = std::fs::read_to_string(&page).unwrap();
    let (begin, end) = (
        "<!-- floors: generated -->\n```text\n",
        "```\n<!-- floors: end -->",
    );
    let (i, j) = (
        text.find(begin).unwrap() + begin.len(),
        text.find(end).unwrap(),
    );
    let picture = floors_picture(&floors_graph());
    if std::env::var_os("HDGEAR_BLESS").is_some() {
        std::fs::write(&page, format!("{}{picture}{}", &text[..i], &text[j..])).unwrap();
    } else {
        assert!(
            text[i..j] == picture,
            "docs/src/architecture.md: the floors are not the code's; rerun with HDGEAR_BLESS=1\n{picture}"
        );
    }
}

/// The drive's equation of motion is written once, as terms (`model/study_terms.rs` and the term
/// files), and every path derives from them; a hand-written acceleration with the study's unit
/// damping (`… − x' − g(x)`) stands only where a benchmark keeps a specialised path, each named
/// here with its measurement (`python3 bench/study_path.py`), and in the cusp passage's normal
/// form, which is another equation (the fast subsystem's local form, not the drive's).
#[test]
fn the_equation_of_motion_is_hand_written_only_where_a_benchmark_keeps_it() {
    // the unit damping's x' subtracted by hand between a load and a stiffness
    const PATTERNS: [&str; 3] = ["- y[1] - ", "- v - self.g(", "- v[j] - "];
    const KEPT: [(&str, &str); 3] = [
        (
            "model.rs",
            "Dimensionless: 2.7-3.2x one trajectory, 5.5-6.1x sixteen lanes (study_path)",
        ),
        (
            "periodic/oscillator.rs",
            "the study's variational recurrence: 7.2x a shooting (study_path/shoot)",
        ),
        (
            "fast/passage.rs",
            "the cusp passage's normal form, not the drive's equation",
        ),
    ];
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut found = Vec::new();
    for file in files_under(&src) {
        if file.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(&file).unwrap());
        let rel = file
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if PATTERNS.iter().any(|p| code.contains(p)) {
            found.push(rel);
        }
    }
    found.sort();
    let stray: Vec<&String> = found
        .iter()
        .filter(|f| !KEPT.iter().any(|k| k.0 == f.as_str()))
        .collect();
    assert!(
        stray.is_empty(),
        "a hand-written equation of motion in {stray:?}"
    );
    // each kept path still is one (else its entry, and its benchmark, go)
    for (file, why) in KEPT {
        assert!(
            found.iter().any(|f| f == file),
            "{file} ({why}) no longer hand-writes it"
        );
    }
}

/// The public type names a line of `code` defines (`pub struct Name`, `pub enum`, `pub trait`,
/// `pub type`), at any indentation.
fn public_type_names(code: &str) -> Vec<String> {
    code.lines()
        .filter_map(|l| {
            let rest = l.trim_start().strip_prefix("pub ")?;
            let rest = ["struct ", "enum ", "trait ", "type "]
                .iter()
                .find_map(|k| rest.strip_prefix(k))?;
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            (!name.is_empty()).then_some(name)
        })
        .collect()
}

/// Each public type name of the library is defined once (issue 99): a reader who meets `Grid` or
/// `Law` knows which one is meant without looking at the path.
#[test]
fn each_public_type_name_is_defined_once() {
    // the scan reads the definitions, not mentions
    assert_eq!(
        public_type_names(
            "pub struct A {\n    pub enum_field: u8,\n  pub enum B<T> {\n// pub trait C\n"
        ),
        ["A", "B"]
    );
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut seen: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for file in files_under(&src) {
        if file.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(&file).unwrap());
        let rel = file.strip_prefix(&src).unwrap().display().to_string();
        for name in public_type_names(&code) {
            seen.entry(name).or_default().push(rel.clone());
        }
    }
    assert!(seen.len() > 300, "the scan saw the library: {}", seen.len());
    let twice: Vec<String> = seen
        .iter()
        .filter(|(_, files)| files.len() > 1)
        .map(|(name, files)| format!("{name}: {}", files.join(", ")))
        .collect();
    assert!(
        twice.is_empty(),
        "defined more than once:\n{}",
        twice.join("\n")
    );
}
