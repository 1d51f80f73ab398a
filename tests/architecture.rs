//! ARCHITECTURE.md's invariants, held against the code: every path it
//! names exists; no crate depends on a crate in a layer above its own (the
//! layers table); no module imports form a cycle in any crate (imports
//! resolved to the file that defines the item, re-exports followed); no
//! command-line or terminal crate (clap, anyhow, indicatif) below the front
//! ends; and the front ends (`src/`, `python/src`) hold no job logic: no
//! function over [`MAX_LOGIC_LINES`] lines of logic that branches or loops.
//!
//! Everything is read as text (no parser crate): the rules are about how
//! the files are laid out and import each other, which text shows.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// The repository root.
fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The longest function the front ends may hold that branches or loops,
/// in lines of logic: lines that are not blank, not comments, and not one
/// field of a struct literal or argument of a call (`name: value,`,
/// `name,`) — a request built from arguments is conversion, however many
/// fields it has.
const MAX_LOGIC_LINES: usize = 30;

/// Crates that only the front ends may use: argument parsing, error
/// erasure, terminal progress bars.
const FRONT_END_ONLY: [&str; 3] = ["clap", "anyhow", "indicatif"];

// ---------------------------------------------------------------------
// Rust source as text: comments, strings and test modules blanked out.

/// `text` with comments and the insides of string and char literals
/// replaced by spaces (line breaks kept), so braces and paths are code.
fn code_only(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    let blank = |c: u8| if c == b'\n' { b'\n' } else { b' ' };
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    out.push(b' ');
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                let mut depth = 0;
                while i < b.len() {
                    if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                        depth += 1;
                        out.extend([b' ', b' ']);
                        i += 2;
                    } else if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                        depth -= 1;
                        out.extend([b' ', b' ']);
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        out.push(blank(b[i]));
                        i += 1;
                    }
                }
            }
            b'r' if matches!(b.get(i + 1), Some(b'"' | b'#'))
                && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) =>
            {
                // A raw string r"..." or r#"..."#.
                let mut j = i + 1;
                let mut hashes = 0;
                while b.get(j) == Some(&b'#') {
                    hashes += 1;
                    j += 1;
                }
                if b.get(j) != Some(&b'"') {
                    out.push(b[i]);
                    i += 1;
                    continue;
                }
                out.extend(std::iter::repeat_n(b' ', j + 1 - i));
                i = j + 1;
                while i < b.len() {
                    if b[i] == b'"'
                        && b[i + 1..].iter().take(hashes).all(|&c| c == b'#')
                        && b.len() >= i + 1 + hashes
                    {
                        out.extend(std::iter::repeat_n(b' ', 1 + hashes));
                        i += 1 + hashes;
                        break;
                    }
                    out.push(blank(b[i]));
                    i += 1;
                }
            }
            b'"' => {
                out.push(b' ');
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    if b[i] == b'\\' && i + 1 < b.len() {
                        out.push(b' ');
                        out.push(blank(b[i + 1]));
                        i += 2;
                    } else {
                        out.push(blank(b[i]));
                        i += 1;
                    }
                }
                out.push(b' ');
                i += 1;
            }
            b'\'' => {
                // A char literal ('x', '\n', '\u{..}') or a lifetime ('a).
                let end = (i + 1..(i + 12).min(b.len())).find(|&j| b[j] == b'\'');
                let is_char = match end {
                    Some(j) => j == i + 2 || (b[i + 1] == b'\\' && j > i + 2),
                    None => false,
                };
                if let (true, Some(j)) = (is_char, end) {
                    out.extend(std::iter::repeat_n(b' ', j + 1 - i));
                    i = j + 1;
                } else {
                    out.push(b'\'');
                    i += 1;
                }
            }
            c => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8(out).expect("ASCII blanks in UTF-8 text")
}

/// The index just past the brace that closes the one at `open`.
fn matching_brace(code: &[u8], open: usize) -> usize {
    let mut depth = 0;
    for (k, &c) in code.iter().enumerate().skip(open) {
        match c {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return k + 1;
                }
            }
            _ => {}
        }
    }
    code.len()
}

/// `code` with every item under `#[cfg(test)]` or `#[test]` blanked out.
fn without_tests(code: &str) -> String {
    let mut b = code.as_bytes().to_vec();
    for marker in ["#[cfg(test)]", "#[test]"] {
        let mut from = 0;
        while let Some(at) = code[from..].find(marker).map(|k| k + from) {
            from = at + marker.len();
            let Some(open) = b[from..].iter().position(|&c| c == b'{').map(|k| k + from) else {
                break;
            };
            // An item without a body (`#[cfg(test)] mod tests;`, a `use`).
            if let Some(semi) = b[from..open].iter().position(|&c| c == b';') {
                b[at..from + semi + 1].iter_mut().for_each(|c| *c = b' ');
                continue;
            }
            let end = matching_brace(&b, open);
            b[at..end]
                .iter_mut()
                .filter(|c| **c != b'\n')
                .for_each(|c| *c = b' ');
            from = end;
        }
    }
    String::from_utf8(b).expect("ASCII blanks in UTF-8 text")
}

/// A path's segments and the index after it (`a::b::{c, d::e}` reads as
/// `a::b` followed by a group).
fn is_ident(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// Every path `prefix::...` in `code` as its segments after `prefix`,
/// groups expanded (`crate::{a::B, c}` gives `a::B` and `c`).
fn paths_after(code: &str, prefix: &str) -> Vec<Vec<String>> {
    let b = code.as_bytes();
    let mut out = Vec::new();
    let mut from = 0;
    let needle = format!("{prefix}::");
    while let Some(at) = code[from..].find(&needle).map(|k| k + from) {
        from = at + needle.len();
        if at > 0 && (is_ident(b[at - 1]) || b[at - 1] == b':') {
            continue;
        }
        expand(b, from, Vec::new(), &mut out);
    }
    out
}

/// The paths starting at `i` (after a `::`), prefixed by `head`.
fn expand(b: &[u8], mut i: usize, mut head: Vec<String>, out: &mut Vec<Vec<String>>) -> usize {
    loop {
        while i < b.len() && b[i].is_ascii_whitespace() {
            i += 1;
        }
        if i < b.len() && b[i] == b'{' {
            i += 1;
            loop {
                while i < b.len() && (b[i].is_ascii_whitespace() || b[i] == b',') {
                    i += 1;
                }
                if i >= b.len() || b[i] == b'}' {
                    return i + 1;
                }
                i = expand(b, i, head.clone(), out);
            }
        }
        let start = i;
        while i < b.len() && is_ident(b[i]) {
            i += 1;
        }
        if start == i {
            out.push(head);
            return i;
        }
        head.push(String::from_utf8_lossy(&b[start..i]).into_owned());
        if b.get(i) == Some(&b':') && b.get(i + 1) == Some(&b':') {
            i += 2;
        } else {
            // `as alias`, a call, the end of a statement.
            out.push(head);
            return i;
        }
    }
}

// ---------------------------------------------------------------------
// Module trees.

/// A crate's modules: path (`["map", "layout"]`) to file, and the files'
/// code without tests.
struct ModuleTree {
    name: String,
    files: BTreeMap<Vec<String>, PathBuf>,
    code: HashMap<PathBuf, String>,
}

impl ModuleTree {
    /// The modules reachable from the crate root `root_file` by `mod`
    /// declarations (inline modules other than tests are not used here).
    fn read(name: &str, root_file: &Path) -> Self {
        let mut tree = ModuleTree {
            name: name.to_string(),
            files: BTreeMap::new(),
            code: HashMap::new(),
        };
        tree.add(Vec::new(), root_file.to_path_buf());
        tree
    }

    fn add(&mut self, module: Vec<String>, file: PathBuf) {
        let code = without_tests(&code_only(&read(&file)));
        let owns_dir = matches!(
            file.file_name().and_then(|n| n.to_str()),
            Some("lib.rs" | "main.rs" | "mod.rs")
        );
        let dir = if owns_dir {
            file.parent().expect("a file has a folder").to_path_buf()
        } else {
            file.with_extension("")
        };
        for child in declared_modules(&code) {
            let candidates = [
                dir.join(format!("{child}.rs")),
                dir.join(&child).join("mod.rs"),
            ];
            let Some(path) = candidates.into_iter().find(|p| p.exists()) else {
                continue;
            };
            let mut m = module.clone();
            m.push(child);
            self.add(m, path);
        }
        self.files.insert(module, file.clone());
        self.code.insert(file, code);
    }

    /// What `module`'s file re-exports: item name to the module path its
    /// `pub use` names (relative paths resolved from `module`).
    fn reexports(&self, module: &[String]) -> HashMap<String, Vec<String>> {
        let mut out = HashMap::new();
        let Some(file) = self.files.get(module) else {
            return out;
        };
        let code = &self.code[file];
        for stmt in statements(code, "pub use ") {
            for path in use_paths(&stmt) {
                let Some((item, from)) = path.split_last() else {
                    continue;
                };
                let base: Vec<String> = match from.first().map(String::as_str) {
                    Some("crate") => from[1..].to_vec(),
                    Some("self") => module.iter().chain(&from[1..]).cloned().collect(),
                    Some("super") => {
                        let mut m = module[..module.len().saturating_sub(1)].to_vec();
                        m.extend(from[1..].iter().cloned());
                        m
                    }
                    _ => module.iter().chain(from).cloned().collect(),
                };
                out.insert(item.clone(), base);
            }
        }
        out
    }

    /// The file that defines what `path` (from the crate root) names: the
    /// deepest module it passes through, following re-exports of the
    /// module it ends in.
    fn resolve(&self, path: &[String]) -> Option<&PathBuf> {
        let mut module: Vec<String> = Vec::new();
        let mut rest = path;
        while let Some((head, tail)) = rest.split_first() {
            let mut next = module.clone();
            next.push(head.clone());
            if !self.files.contains_key(&next) {
                break;
            }
            module = next;
            rest = tail;
        }
        // `crate::Item` or `crate::wing::Item`: follow the re-export to
        // its module (once more if that module re-exports it too).
        for _ in 0..4 {
            let Some(item) = rest.first() else { break };
            let Some(target) = self.reexports(&module).get(item).cloned() else {
                break;
            };
            if target == module || !self.files.contains_key(&target) {
                break;
            }
            module = target;
        }
        self.files.get(&module)
    }

    /// The import graph: each file to the files its code names (`crate::`,
    /// `super::`, `self::` paths), re-exports and module declarations
    /// aside.
    fn imports(&self) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
        let mut graph: BTreeMap<PathBuf, BTreeSet<PathBuf>> = BTreeMap::new();
        for (module, file) in &self.files {
            let code = strip_statements(&self.code[file], &["pub use ", "pub(crate) use "]);
            let mut targets = BTreeSet::new();
            for path in paths_after(&code, "crate") {
                targets.extend(self.resolve(&path).cloned());
            }
            for (prefix, up) in [("super", 1usize), ("self", 0)] {
                for path in paths_after(&code, prefix) {
                    let mut full = module[..module.len().saturating_sub(up)].to_vec();
                    full.extend(path);
                    targets.extend(self.resolve(&full).cloned());
                }
            }
            targets.remove(file);
            graph.entry(file.clone()).or_default().extend(targets);
        }
        graph
    }
}

/// The names of `mod name;` declarations in `code`.
fn declared_modules(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in code.lines() {
        let t = line.trim();
        let t = t
            .strip_prefix("pub ")
            .or_else(|| t.strip_prefix("pub(crate) "))
            .unwrap_or(t);
        if let Some(name) = t.strip_prefix("mod ").and_then(|r| r.strip_suffix(';')) {
            out.push(name.trim().to_string());
        }
    }
    out
}

/// Where the statements of `code` that start with `keyword` lie: from the
/// keyword to their `;`.
fn statement_spans(code: &str, keyword: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(at) = code[from..].find(keyword).map(|k| k + from) {
        let end = code[at..].find(';').map_or(code.len(), |k| k + at);
        if at == 0 || code.as_bytes()[at - 1].is_ascii_whitespace() {
            out.push((at, end));
        }
        from = end;
    }
    out
}

/// The statements of `code` that start with `keyword` (up to their `;`).
fn statements(code: &str, keyword: &str) -> Vec<String> {
    statement_spans(code, keyword)
        .into_iter()
        .map(|(at, end)| code[at + keyword.len()..end].to_string())
        .collect()
}

/// `code` with the statements starting with any of `keywords` blanked.
fn strip_statements(code: &str, keywords: &[&str]) -> String {
    let mut b = code.as_bytes().to_vec();
    for (at, end) in keywords.iter().flat_map(|k| statement_spans(code, k)) {
        b[at..end]
            .iter_mut()
            .filter(|c| **c != b'\n')
            .for_each(|c| *c = b' ');
    }
    String::from_utf8(b).expect("ASCII blanks in UTF-8 text")
}

/// The paths of one `use` statement's body (`a::b::{C, d::E}`).
fn use_paths(stmt: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    expand(stmt.as_bytes(), 0, Vec::new(), &mut out);
    out.retain(|p| !p.is_empty());
    out
}

/// The files on a cycle of `graph`, each cycle as its files in order.
fn cycles(graph: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Vec<Vec<PathBuf>> {
    // Tarjan's strongly connected components.
    struct State<'a> {
        graph: &'a BTreeMap<PathBuf, BTreeSet<PathBuf>>,
        index: HashMap<&'a PathBuf, usize>,
        low: HashMap<&'a PathBuf, usize>,
        stack: Vec<&'a PathBuf>,
        on_stack: BTreeSet<&'a PathBuf>,
        out: Vec<Vec<PathBuf>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a PathBuf) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in s.graph.get(v).into_iter().flatten() {
            if !s.graph.contains_key(w) {
                continue;
            }
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(lw);
            } else if s.on_stack.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(iw);
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
                s.out.push(component);
            }
        }
    }
    let mut s = State {
        graph,
        index: HashMap::new(),
        low: HashMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

/// Every crate of the checkout with its root file: the library crates,
/// the binary, the Python package's extension.
fn crates() -> Vec<(String, PathBuf)> {
    let mut out = vec![
        ("shlight".to_string(), root().join("src/main.rs")),
        (
            "shlight-python".to_string(),
            root().join("python/src/lib.rs"),
        ),
    ];
    for entry in std::fs::read_dir(root().join("crates")).expect("crates/") {
        let dir = entry.expect("a crate folder").path();
        let lib = dir.join("src/lib.rs");
        if lib.exists() {
            let name = dir
                .file_name()
                .expect("a name")
                .to_string_lossy()
                .into_owned();
            out.push((name, lib));
        }
    }
    out.sort();
    out
}

/// A crate's `Cargo.toml` beside its source.
fn manifest(crate_root: &Path) -> PathBuf {
    let mut dir = crate_root.parent().expect("src/");
    while !dir.join("Cargo.toml").exists() {
        dir = dir.parent().expect("a Cargo.toml above");
    }
    dir.join("Cargo.toml")
}

/// The dependencies (not dev- or build-) a manifest names.
fn dependencies(manifest: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_deps = false;
    for line in read(manifest).lines() {
        let t = line.trim();
        if t.starts_with('[') {
            in_deps = t == "[dependencies]" || t.ends_with(".dependencies]") && !t.contains("dev-");
            continue;
        }
        if !in_deps || t.starts_with('#') || t.is_empty() {
            continue;
        }
        if let Some((name, _)) = t.split_once('=') {
            let name = name.trim();
            let name = name.split('.').next().unwrap_or(name);
            out.push(name.trim_matches('"').to_string());
        }
    }
    out
}

// ---------------------------------------------------------------------
// ARCHITECTURE.md.

/// The layers table of ARCHITECTURE.md, top (front ends) first: each
/// row's crates, named in backticks.
fn layers(doc: &str) -> Vec<(String, Vec<String>)> {
    let section = doc
        .split("\n## ")
        .find(|s| s.starts_with("Layers"))
        .expect("ARCHITECTURE.md has a \"## Layers\" section");
    let mut out = Vec::new();
    for line in section.lines().filter(|l| l.starts_with('|')) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        if cells.len() < 2 || cells[0].starts_with('-') || cells[0] == "layer" {
            continue;
        }
        let crates = cells[1]
            .split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect();
        out.push((cells[0].to_string(), crates));
    }
    out
}

/// Every backticked path in `doc`: a token with a `/`, or ending in a
/// file extension the project keeps, written from the repository root.
fn named_paths(doc: &str) -> Vec<String> {
    let extensions = [
        ".rs", ".md", ".wgsl", ".toml", ".py", ".sh", ".json", ".ipynb", ".html", ".js",
    ];
    doc.split('`')
        .skip(1)
        .step_by(2)
        .filter(|t| {
            !t.contains(' ') && !t.contains("::") && !t.starts_with("--") && !t.contains('{')
        })
        .filter(|t| t.contains('/') || extensions.iter().any(|e| t.ends_with(e)))
        .filter(|t| !t.starts_with("http") && !t.starts_with('/') && !t.contains("*"))
        .map(str::to_string)
        .collect()
}

// ---------------------------------------------------------------------
// The tests.

#[test]
fn every_path_architecture_md_names_exists() {
    let doc = read(&root().join("ARCHITECTURE.md"));
    let paths = named_paths(&doc);
    assert!(paths.len() > 20, "paths found: {paths:?}");
    let missing: Vec<&String> = paths.iter().filter(|p| !root().join(p).exists()).collect();
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md names paths that do not exist: {missing:?}"
    );
}

#[test]
fn no_crate_depends_on_a_crate_above_it() {
    let doc = read(&root().join("ARCHITECTURE.md"));
    let layers = layers(&doc);
    let layer_of: HashMap<&str, usize> = layers
        .iter()
        .enumerate()
        .flat_map(|(k, (_, crates))| crates.iter().map(move |c| (c.as_str(), k)))
        .collect();
    let mut problems = Vec::new();
    for (name, root_file) in crates() {
        let Some(&mine) = layer_of.get(name.as_str()) else {
            problems.push(format!("{name} is in no layer of ARCHITECTURE.md"));
            continue;
        };
        for dep in dependencies(&manifest(&root_file)) {
            if let Some(&theirs) = layer_of.get(dep.as_str())
                && theirs < mine
            {
                problems.push(format!(
                    "{name} ({}) depends on {dep} ({}), a layer above it",
                    layers[mine].0, layers[theirs].0
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{problems:#?}");
}

#[test]
fn no_module_imports_form_a_cycle() {
    let mut found = Vec::new();
    for (name, root_file) in crates() {
        let tree = ModuleTree::read(&name, &root_file);
        assert!(
            tree.files.len() > 1 || name == "shlight-baked",
            "{name}: modules {:?}",
            tree.files
        );
        for cycle in cycles(&tree.imports()) {
            let files: Vec<String> = cycle
                .iter()
                .map(|p| p.strip_prefix(root()).unwrap_or(p).display().to_string())
                .collect();
            found.push(format!("{}: {}", tree.name, files.join(" <-> ")));
        }
    }
    assert!(found.is_empty(), "module cycles:\n{}", found.join("\n"));
}

#[test]
fn the_cycle_finder_finds_a_cycle_through_a_reexport() {
    // a.rs uses b's item through the root's re-export; b.rs uses a.
    let dir = crate::util::temp_dir("architecture_cycle");
    std::fs::create_dir_all(dir.join("src")).unwrap();
    std::fs::write(
        dir.join("src/lib.rs"),
        "mod a;\nmod b;\nmod c;\npub use b::Thing;\n",
    )
    .unwrap();
    std::fs::write(dir.join("src/a.rs"), "use crate::Thing;\npub fn f() {}\n").unwrap();
    std::fs::write(
        dir.join("src/b.rs"),
        "pub struct Thing;\nfn g() { crate::a::f() }\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("src/c.rs"),
        "// crate::a::f in a comment\nconst S: &str = \"crate::b::Thing\";\n#[cfg(test)]\nmod tests { use crate::a::f; }\n",
    )
    .unwrap();
    let tree = ModuleTree::read("t", &dir.join("src/lib.rs"));
    let found = cycles(&tree.imports());
    assert_eq!(found, [vec![dir.join("src/a.rs"), dir.join("src/b.rs")]]);
    // c.rs names a and b only in a comment, a string and its tests.
    assert!(tree.imports()[&dir.join("src/c.rs")].is_empty());
}

#[test]
fn no_command_line_or_terminal_crate_below_the_front_ends() {
    let mut problems = Vec::new();
    for (name, root_file) in crates() {
        if name == "shlight" {
            continue;
        }
        for dep in dependencies(&manifest(&root_file)) {
            if FRONT_END_ONLY.contains(&dep.as_str()) {
                problems.push(format!("{name} depends on {dep}"));
            }
        }
    }
    assert!(problems.is_empty(), "{problems:?}");
}

/// Each `fn` of `code` (tests blanked): its name, first line and the lines
/// of its body.
fn functions(code: &str) -> Vec<(String, usize, Vec<String>)> {
    let b = code.as_bytes();
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(at) = code[from..].find("fn ").map(|k| k + from) {
        from = at + 3;
        if at > 0 && is_ident(b[at - 1]) {
            continue;
        }
        let name: String = code[from..]
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if name.is_empty() {
            continue;
        }
        // The body: the first `{` before any `;` (a declaration has none).
        let Some(open) = code[from..].find(['{', ';']).map(|k| k + from) else {
            break;
        };
        if b[open] == b';' {
            continue;
        }
        let end = matching_brace(b, open);
        let line = code[..at].lines().count() + 1;
        let body = code[open + 1..end - 1]
            .lines()
            .map(str::to_string)
            .collect();
        out.push((name, line, body));
        from = open + 1;
    }
    out
}

/// Lines of logic of a body ([`MAX_LOGIC_LINES`]).
fn logic_lines(body: &[String]) -> usize {
    body.iter()
        .map(|l| l.trim())
        .filter(|l| !l.is_empty())
        .filter(|l| {
            // One field or argument: `name,` or `name: value,`.
            let field = l.strip_suffix(',').is_some_and(|f| {
                let head: String = f
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                !head.is_empty()
                    && head
                        .chars()
                        .next()
                        .is_some_and(|c| c.is_ascii_lowercase() || c == '_')
                    && (f.len() == head.len() || f[head.len()..].starts_with(": "))
            });
            !field
        })
        .count()
}

/// Whether a body branches or loops.
fn branches(body: &[String]) -> bool {
    body.iter().any(|l| {
        l.split(|c: char| !(c.is_alphanumeric() || c == '_'))
            .any(|w| matches!(w, "if" | "match" | "for" | "while" | "loop"))
    })
}

/// The front ends' functions that do more than convert and call.
fn job_logic_in(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut files = vec![dir.to_path_buf()];
    while let Some(p) = files.pop() {
        if p.is_dir() {
            files.extend(std::fs::read_dir(&p).unwrap().map(|e| e.unwrap().path()));
            continue;
        }
        if p.extension().and_then(|e| e.to_str()) != Some("rs") {
            continue;
        }
        let code = without_tests(&code_only(&read(&p)));
        for (name, line, body) in functions(&code) {
            let n = logic_lines(&body);
            if n > MAX_LOGIC_LINES && branches(&body) {
                let file = p.strip_prefix(root()).unwrap_or(&p).display();
                found.push(format!("{file}:{line} {name}: {n} lines of logic"));
            }
        }
    }
    found.sort();
    found
}

#[test]
fn the_front_ends_convert_and_call() {
    let mut found = job_logic_in(&root().join("src"));
    found.extend(job_logic_in(&root().join("python/src")));
    assert!(
        found.is_empty(),
        "functions of the front ends over {MAX_LOGIC_LINES} lines of logic that branch or loop \
         (move the logic into a library job):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_logic_counter_counts_logic_not_fields() {
    let body: Vec<String> = [
        "let plan = Request {",
        "    mesh: &args.mesh,",
        "    lmax,",
        "    // a comment blanked to spaces",
        "    preview: args.preview.as_deref(),",
        "}",
        ".check(Spelling::CommandLine)?;",
        "if plan.ok() { run(&plan)?; }",
    ]
    .map(str::to_string)
    .to_vec();
    assert_eq!(logic_lines(&body), 5);
    assert!(branches(&body));
    assert!(!branches(&body[..3]));
    let code = "fn a() { let x = 1; }\nfn b();\nfn c(y: u8) -> u8 { if y > 0 { y } else { 0 } }\n";
    let fns = functions(code);
    let names: Vec<&str> = fns.iter().map(|f| f.0.as_str()).collect();
    assert_eq!(names, ["a", "c"]);
    assert_eq!(fns[1].1, 3);
}
