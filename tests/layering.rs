//! Import cycles and layering, at file granularity, from the sources alone (std only).
//!
//! Every `.rs` file under `engine/src` (crate `lumen`) and `game/src` (crate `lumen_game`;
//! `game/src/main.rs` is a crate of its own that sees `lumen_game`) is a node. A path that
//! names a module or an item of this crate — in a `use` tree or in code: `crate::…`,
//! `super::…`, `self::…`, a child module's name, a name the module imported, and in
//! `main.rs` `lumen_game::…` — is an edge to the file that defines what it names: the
//! longest prefix of the path that is a module file, followed through that module's
//! imports (`pub use` re-exports and private `use`s alike) when the next segment is not
//! an item defined in that file. `mod x;` declarations are not edges, comments and
//! literals are skipped, and an inline `mod tests { use super::*; }` is its own file.
//!
//! The tests fail on every strongly connected component of more than one file (Tarjan),
//! listing cycles as `a.rs -> b.rs -> a.rs`, and on any edge from the engine's layers
//! below the renderer (`scene/`, `brdf.rs`, `reference/`, `rays/`, `validate.rs`,
//! `workflow.rs`)
//! into `engine/src/render/`.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet, VecDeque};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Files of the engine that must not depend on the renderer.
const BELOW_RENDER: &[&str] = &[
    "engine/src/scene/",
    "engine/src/shading/brdf.rs",
    "engine/src/reference/",
    "engine/src/rays/",
    "engine/src/validate.rs",
    "engine/src/workflow.rs",
];

/// The renderer.
const RENDER: &str = "engine/src/render/";

/// A module: the crate it belongs to and its path from the crate root.
type ModulePath = (String, Vec<String>);

/// One source file: its name relative to the repository root and its text.
struct Source {
    name: String,
    text: String,
}

/// The crate and module path of a file named relative to the repository root, and the
/// other crates it may name by their crate name.
fn module_of(name: &str) -> Option<(ModulePath, Vec<(&'static str, &'static str)>)> {
    let (krate, rest, externs) = if let Some(rest) = name.strip_prefix("engine/src/") {
        ("lumen", rest, vec![])
    } else if name == "game/src/main.rs" {
        return Some((
            ("lumen (bin)".into(), vec![]),
            vec![("lumen_game", "lumen_game")],
        ));
    } else if let Some(rest) = name.strip_prefix("game/src/") {
        ("lumen_game", rest, vec![])
    } else {
        return None;
    };
    let stem = rest.strip_suffix(".rs")?;
    let mut segments: Vec<String> = stem.split('/').map(str::to_string).collect();
    if matches!(segments.last().map(String::as_str), Some("mod"))
        || (segments.len() == 1 && segments[0] == "lib")
    {
        segments.pop();
    }
    Some(((krate.into(), segments), externs))
}

/// `text` with comments removed and string, byte-string, raw-string and character
/// literals emptied (`""`, `' '`); lifetimes and line breaks are kept.
fn strip(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let ident = |k: usize| c[k].is_alphanumeric() || c[k] == '_';
    while i < c.len() {
        match c[i] {
            '/' if c.get(i + 1) == Some(&'/') => {
                while i < c.len() && c[i] != '\n' {
                    i += 1;
                }
            }
            '/' if c.get(i + 1) == Some(&'*') => {
                let mut depth = 0;
                while i < c.len() {
                    if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                        depth += 1;
                        i += 2;
                    } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        if c[i] == '\n' {
                            out.push('\n');
                        }
                        i += 1;
                    }
                }
                out.push(' ');
            }
            'r' | 'b'
                if (i == 0 || !ident(i - 1))
                    && matches!(
                        (c[i], c.get(i + 1), c.get(i + 2)),
                        ('r', Some('"' | '#'), _) | ('b', Some('r'), Some('"' | '#'))
                    ) =>
            {
                // A raw string: r"…", r#"…"#, br"…"; r#ident is a raw identifier.
                let mut j = i + if c[i] == 'b' { 2 } else { 1 };
                let hashes = c[j..].iter().take_while(|&&h| h == '#').count();
                j += hashes;
                if c.get(j) != Some(&'"') {
                    out.push(c[i]);
                    i += 1;
                    continue;
                }
                j += 1;
                while j < c.len() {
                    if c[j] == '"'
                        && c[j + 1..]
                            .iter()
                            .take(hashes)
                            .filter(|&&h| h == '#')
                            .count()
                            == hashes
                    {
                        j += 1 + hashes;
                        break;
                    }
                    if c[j] == '\n' {
                        out.push('\n');
                    }
                    j += 1;
                }
                out.push_str("\"\"");
                i = j;
            }
            '"' => {
                i += 1;
                while i < c.len() && c[i] != '"' {
                    if c[i] == '\n' {
                        out.push('\n');
                    }
                    i += if c[i] == '\\' { 2 } else { 1 };
                }
                i += 1;
                out.push_str("\"\"");
            }
            '\'' => {
                // A character literal ('x', '\n', '\u{1F600}') or a lifetime ('a).
                if c.get(i + 1) == Some(&'\\') {
                    let mut j = i + 2;
                    while j < c.len() && c[j] != '\'' {
                        j += 1;
                    }
                    out.push_str("' '");
                    i = j + 1;
                } else if c.get(i + 2) == Some(&'\'') {
                    out.push_str("' '");
                    i += 3;
                } else {
                    out.push('\'');
                    i += 1;
                }
            }
            ch => {
                out.push(ch);
                i += 1;
            }
        }
    }
    out
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Ident(String),
    /// `::`
    PathSep,
    Punct(char),
}

/// Identifiers, `::` and single punctuation characters with their line numbers; numbers
/// and whitespace are dropped.
fn tokens(text: &str) -> Vec<(Token, usize)> {
    let c: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    while i < c.len() {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch.is_alphanumeric() || ch == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            if !ch.is_ascii_digit() {
                out.push((Token::Ident(c[start..i].iter().collect()), line));
            }
        } else if ch == ':' && c.get(i + 1) == Some(&':') {
            out.push((Token::PathSep, line));
            i += 2;
        } else {
            out.push((Token::Punct(ch), line));
            i += 1;
        }
    }
    out
}

/// One name a `use` tree brings in.
#[derive(Clone, Debug, PartialEq)]
struct UseItem {
    /// The path as written (`self` at the end of a group removed).
    segments: Vec<String>,
    /// The name it is known by in the module (`None`: a glob or `as _`).
    alias: Option<String>,
}

/// Parses the use tree starting at `i` (after `use`) into `out`; returns the index after
/// the tree.
fn use_tree(
    t: &[(Token, usize)],
    mut i: usize,
    prefix: &[String],
    out: &mut Vec<UseItem>,
) -> usize {
    let mut segments = prefix.to_vec();
    if t.get(i).map(|t| &t.0) == Some(&Token::PathSep) {
        // `::name`: always an external crate.
        segments.push("::".into());
        i += 1;
    }
    while let Some((token, _)) = t.get(i) {
        match token {
            Token::Punct('{') => {
                i += 1;
                while let Some((token, _)) = t.get(i) {
                    match token {
                        Token::Punct('}') => return i + 1,
                        Token::Punct(',') => i += 1,
                        _ => i = use_tree(t, i, &segments, out),
                    }
                }
                return i;
            }
            Token::Punct('*') => {
                out.push(UseItem {
                    segments,
                    alias: None,
                });
                return i + 1;
            }
            Token::Ident(name) => {
                let mut alias = Some(name.clone());
                if name == "self" && !segments.is_empty() {
                    alias = segments.last().cloned();
                } else {
                    segments.push(name.clone());
                }
                i += 1;
                match t.get(i).map(|t| &t.0) {
                    Some(Token::PathSep) => {
                        i += 1;
                        continue;
                    }
                    Some(Token::Ident(kw)) if kw == "as" => {
                        alias = match t.get(i + 1).map(|t| &t.0) {
                            Some(Token::Ident(a)) if a != "_" => Some(a.clone()),
                            _ => None,
                        };
                        i += 2;
                    }
                    _ => {}
                }
                out.push(UseItem { segments, alias });
                return i;
            }
            _ => return i + 1,
        }
    }
    i
}

/// What a module (a file, or an inline `mod x { … }` in one) defines and imports.
#[derive(Default)]
struct Module {
    file: usize,
    /// Items defined at the module's top level.
    defs: HashSet<String>,
    /// Names brought in by `use`, and the path each names (as written).
    imports: HashMap<String, Vec<String>>,
}

/// A path found in a file, to resolve once every module is known.
struct Reference {
    file: usize,
    /// The module the path is written in.
    context: ModulePath,
    segments: Vec<String>,
    line: usize,
    /// A `use` path ending in `*`.
    glob: bool,
}

/// A `#[macro_export]` macro: named at its crate's root, defined in its own file.
type ExportedMacros = HashMap<(String, String), usize>;

/// The module graph of a set of files.
struct Graph {
    names: Vec<String>,
    /// Per node, the nodes it depends on and the first place it does
    /// (`file:line`, the path written there).
    edges: Vec<BTreeMap<usize, (String, String)>>,
}

const ITEM_KEYWORDS: &[&str] = &[
    "fn", "struct", "enum", "trait", "type", "const", "static", "union", "mod",
];

/// Builds the graph of `sources` (named relative to the repository root).
fn graph(sources: &[Source]) -> Graph {
    let mut modules: HashMap<ModulePath, Module> = HashMap::new();
    let mut exported = ExportedMacros::new();
    let mut externs: Vec<Vec<(&str, &str)>> = Vec::new();
    let mut references = Vec::new();
    for (file, source) in sources.iter().enumerate() {
        let Some((root, file_externs)) = module_of(&source.name) else {
            externs.push(Vec::new());
            continue;
        };
        externs.push(file_externs);
        modules.entry(root.clone()).or_default().file = file;
        let t = tokens(&strip(&source.text));
        // Inline modules open at a brace depth; the module's items sit one deeper.
        let mut stack: Vec<(String, usize)> = Vec::new();
        let mut depth = 0;
        let context = |stack: &[(String, usize)]| {
            let mut m = root.clone();
            m.1.extend(stack.iter().map(|(n, _)| n.clone()));
            m
        };
        let mut i = 0;
        while i < t.len() {
            let top_level = depth == stack.last().map_or(0, |(_, d)| d + 1);
            match &t[i].0 {
                Token::Punct('{') => depth += 1,
                Token::Punct('}') => {
                    depth = depth.saturating_sub(1);
                    if stack.last().is_some_and(|(_, d)| *d == depth) {
                        stack.pop();
                    }
                }
                Token::Ident(kw) if kw == "use" => {
                    let mut items = Vec::new();
                    let line = t[i].1;
                    i = use_tree(&t, i + 1, &[], &mut items);
                    let here = context(&stack);
                    for item in items {
                        if top_level && let Some(alias) = &item.alias {
                            modules
                                .entry(here.clone())
                                .or_default()
                                .imports
                                .insert(alias.clone(), item.segments.clone());
                        }
                        references.push(Reference {
                            file,
                            context: here.clone(),
                            glob: item.alias.is_none(),
                            segments: item.segments,
                            line,
                        });
                    }
                    continue;
                }
                Token::Ident(kw) if ITEM_KEYWORDS.contains(&kw.as_str()) || kw == "macro_rules" => {
                    let mut j = i + 1;
                    if kw == "macro_rules" && t.get(j).map(|t| &t.0) == Some(&Token::Punct('!')) {
                        j += 1;
                    }
                    if let Some(Token::Ident(name)) = t.get(j).map(|t| &t.0)
                        && name != "fn"
                    {
                        // `#[macro_export]` in the attributes just before it.
                        let attributes = t[..i]
                            .iter()
                            .rev()
                            .take_while(|(tok, _)| {
                                !matches!(
                                    tok,
                                    Token::Punct(';') | Token::Punct('}') | Token::Punct('{')
                                )
                            })
                            .any(|(tok, _)| *tok == Token::Ident("macro_export".into()));
                        if kw == "macro_rules" && attributes {
                            exported.insert((root.0.clone(), name.clone()), file);
                        }
                        if top_level {
                            let here = context(&stack);
                            modules.entry(here).or_default().defs.insert(name.clone());
                        }
                        if kw == "mod" && t.get(j + 1).map(|t| &t.0) == Some(&Token::Punct('{')) {
                            let mut inner = context(&stack);
                            inner.1.push(name.clone());
                            modules.entry(inner).or_default().file = file;
                            stack.push((name.clone(), depth));
                            depth += 1;
                            i = j + 2;
                            continue;
                        }
                        i = j + 1;
                        continue;
                    }
                }
                Token::Ident(head) if t.get(i + 1).map(|t| &t.0) == Some(&Token::PathSep) => {
                    if i > 0 && t[i - 1].0 == Token::PathSep {
                        i += 1;
                        continue;
                    }
                    let line = t[i].1;
                    let mut segments = vec![head.clone()];
                    let mut j = i + 1;
                    while t.get(j).map(|t| &t.0) == Some(&Token::PathSep) {
                        match t.get(j + 1).map(|t| &t.0) {
                            Some(Token::Ident(s)) => segments.push(s.clone()),
                            _ => break,
                        }
                        j += 2;
                    }
                    references.push(Reference {
                        file,
                        context: context(&stack),
                        segments,
                        line,
                        glob: false,
                    });
                    i = j;
                    continue;
                }
                _ => {}
            }
            i += 1;
        }
    }

    let resolver = Resolver {
        modules: &modules,
        exported: &exported,
        externs: &externs,
    };
    let mut edges = vec![BTreeMap::new(); sources.len()];
    for r in &references {
        let Some(target) = resolver.target(r) else {
            continue;
        };
        if target != r.file {
            edges[r.file].entry(target).or_insert_with(|| {
                let at = format!("{}:{}", sources[r.file].name, r.line);
                (at, r.segments.join("::"))
            });
        }
    }
    Graph {
        names: sources.iter().map(|s| s.name.clone()).collect(),
        edges,
    }
}

struct Resolver<'a> {
    modules: &'a HashMap<ModulePath, Module>,
    exported: &'a ExportedMacros,
    externs: &'a [Vec<(&'static str, &'static str)>],
}

impl Resolver<'_> {
    /// The file a reference depends on; `None` for other crates and unknown names.
    fn target(&self, r: &Reference) -> Option<usize> {
        let path = self.absolute(r.file, &r.context, &r.segments, 0)?;
        self.file_of(&path, r.glob, 0)
    }

    /// `segments` written in module `context` of `file`, from its crate's root.
    fn absolute(
        &self,
        file: usize,
        context: &ModulePath,
        segments: &[String],
        depth: usize,
    ) -> Option<ModulePath> {
        let (head, rest) = segments.split_first()?;
        match head.as_str() {
            "crate" => Some((context.0.clone(), rest.to_vec())),
            "self" => Some((context.0.clone(), [&context.1[..], rest].concat())),
            "super" => {
                let mut base = context.1.clone();
                let mut rest = segments;
                while rest.first().map(String::as_str) == Some("super") {
                    base.pop()?;
                    rest = &rest[1..];
                }
                Some((context.0.clone(), [&base[..], rest].concat()))
            }
            _ => {
                if let Some((_, krate)) = self.externs[file].iter().find(|(n, _)| n == head) {
                    return Some(((*krate).into(), rest.to_vec()));
                }
                let child = (
                    context.0.clone(),
                    [&context.1[..], std::slice::from_ref(head)].concat(),
                );
                if self.modules.contains_key(&child) {
                    return Some((context.0.clone(), [&context.1[..], segments].concat()));
                }
                let imported = self.modules.get(context)?.imports.get(head)?;
                if depth > 16 || (imported.len() == 1 && imported.first() == Some(head)) {
                    return None;
                }
                let mut path = self.absolute(file, context, imported, depth + 1)?;
                path.1.extend_from_slice(rest);
                Some(path)
            }
        }
    }

    /// The file defining what the absolute `path` names: the longest prefix that is a
    /// module, then the item after it through that module's imports.
    fn file_of(&self, path: &ModulePath, glob: bool, depth: usize) -> Option<usize> {
        let (krate, segments) = path;
        let k = (0..=segments.len()).rev().find(|&k| {
            self.modules
                .contains_key(&(krate.clone(), segments[..k].to_vec()))
        })?;
        let prefix = (krate.clone(), segments[..k].to_vec());
        let module = &self.modules[&prefix];
        let Some(name) = segments.get(k) else {
            return Some(module.file);
        };
        if glob || module.defs.contains(name) || depth > 16 {
            return Some(module.file);
        }
        if k == 0
            && let Some(&file) = self.exported.get(&(krate.clone(), name.clone()))
        {
            return Some(file);
        }
        let Some(imported) = module.imports.get(name) else {
            return Some(module.file);
        };
        let file = module.file;
        match self.absolute(file, &prefix, imported, depth + 1) {
            Some(mut target) => {
                target.1.extend_from_slice(&segments[k + 1..]);
                self.file_of(&target, glob, depth + 1)
            }
            // Imported from another crate.
            None => Some(file),
        }
    }
}

/// Strongly connected components of more than one file (Tarjan 1972), each sorted.
fn cycles_components(g: &Graph) -> Vec<Vec<usize>> {
    struct Tarjan<'a> {
        g: &'a Graph,
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    impl Tarjan<'_> {
        fn visit(&mut self, v: usize) {
            self.index[v] = Some(self.next);
            self.low[v] = self.next;
            self.next += 1;
            self.stack.push(v);
            self.on_stack[v] = true;
            let targets: Vec<usize> = self.g.edges[v].keys().copied().collect();
            for w in targets {
                match self.index[w] {
                    None => {
                        self.visit(w);
                        self.low[v] = self.low[v].min(self.low[w]);
                    }
                    Some(i) if self.on_stack[w] => self.low[v] = self.low[v].min(i),
                    Some(_) => {}
                }
            }
            if Some(self.low[v]) == self.index[v] {
                let mut component = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on_stack[w] = false;
                    component.push(w);
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort_by(|a, b| self.g.names[*a].cmp(&self.g.names[*b]));
                    self.out.push(component);
                }
            }
        }
    }
    let n = g.names.len();
    let mut t = Tarjan {
        g,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            t.visit(v);
        }
    }
    let mut out = t.out;
    out.sort_by(|a, b| g.names[a[0]].cmp(&g.names[b[0]]));
    out
}

/// Per component, the shortest cycle through each of its files, without repeats; each
/// starts at its alphabetically first file.
fn cycles(g: &Graph) -> Vec<Vec<usize>> {
    let mut out = BTreeSet::new();
    for component in cycles_components(g) {
        let inside: HashSet<usize> = component.iter().copied().collect();
        for &start in &component {
            // Breadth-first from `start` back to it, inside the component.
            let mut parent: HashMap<usize, usize> = HashMap::new();
            let mut queue = VecDeque::from([start]);
            let mut found = None;
            while let Some(v) = queue.pop_front() {
                for &w in g.edges[v].keys() {
                    if w == start {
                        found = Some(v);
                        break;
                    }
                    if inside.contains(&w) && !parent.contains_key(&w) {
                        parent.insert(w, v);
                        queue.push_back(w);
                    }
                }
                if found.is_some() {
                    break;
                }
            }
            let Some(mut v) = found else { continue };
            let mut cycle = vec![v];
            while v != start {
                v = parent[&v];
                cycle.push(v);
            }
            cycle.reverse();
            let first = (0..cycle.len())
                .min_by(|&a, &b| g.names[cycle[a]].cmp(&g.names[cycle[b]]))
                .unwrap_or(0);
            cycle.rotate_left(first);
            out.insert(
                cycle
                    .iter()
                    .map(|&f| g.names[f].clone())
                    .collect::<Vec<_>>(),
            );
        }
    }
    let index: HashMap<&str, usize> = g
        .names
        .iter()
        .enumerate()
        .map(|(i, n)| (n.as_str(), i))
        .collect();
    out.into_iter()
        .map(|c| c.iter().map(|n| index[n.as_str()]).collect())
        .collect()
}

/// The graph between sibling modules: an edge from file `a` to file `b` of the same crate
/// is an edge between the two children of their deepest common module that hold them
/// (`bench/mod.rs -> view/window.rs` is `bench -> view`). Edges between a module's own
/// file and its descendants are left out. Nodes are named like files (`game/src/bench`,
/// `engine/src/shading/brdf.rs`).
fn sibling_graph(g: &Graph) -> Graph {
    let modules: Vec<Option<ModulePath>> = g
        .names
        .iter()
        .map(|n| module_of(n).map(|(m, _)| m))
        .collect();
    let mut names: Vec<String> = Vec::new();
    let mut index: HashMap<String, usize> = HashMap::new();
    let mut edges: Vec<BTreeMap<usize, (String, String)>> = Vec::new();
    let mut node = |name: String, edges: &mut Vec<BTreeMap<_, _>>| {
        *index.entry(name.clone()).or_insert_with(|| {
            names.push(name);
            edges.push(BTreeMap::new());
            names.len() - 1
        })
    };
    for (a, targets) in g.edges.iter().enumerate() {
        for (&b, evidence) in targets {
            let (Some(ma), Some(mb)) = (&modules[a], &modules[b]) else {
                continue;
            };
            if ma.0 != mb.0 {
                continue;
            }
            let common = ma.1.iter().zip(&mb.1).take_while(|(x, y)| x == y).count();
            if common == ma.1.len() || common == mb.1.len() {
                continue;
            }
            // The child of the common module that holds each file: a folder if the file
            // is below it, else the file itself.
            let holder = |file: usize, m: &ModulePath| {
                let name = &g.names[file];
                let below = m.1.len() > common + 1 || name.ends_with("/mod.rs");
                let prefix = &name[..name.find("/src/").map_or(0, |i| i + 5)];
                let mut path = format!("{prefix}{}", m.1[..=common].join("/"));
                if !below {
                    path.push_str(".rs");
                }
                path
            };
            let from = node(holder(a, ma), &mut edges);
            let to = node(holder(b, mb), &mut edges);
            edges[from].entry(to).or_insert_with(|| evidence.clone());
        }
    }
    Graph { names, edges }
}

/// `a.rs -> b.rs -> a.rs`, then where each step is written.
fn describe(g: &Graph, cycle: &[usize]) -> String {
    let mut names: Vec<&str> = cycle.iter().map(|&f| g.names[f].as_str()).collect();
    names.push(names[0]);
    let mut text = names.join(" -> ");
    for (k, &from) in cycle.iter().enumerate() {
        let to = cycle[(k + 1) % cycle.len()];
        if let Some((at, path)) = g.edges[from].get(&to) {
            let _ = write!(text, "\n    {at}: {path}");
        }
    }
    text
}

/// Every `.rs` file under `dir`, named relative to `root`.
fn rust_files(root: &Path, dir: &Path, out: &mut Vec<Source>) -> std::io::Result<()> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)?
        .map(|e| e.map(|e| e.path()))
        .collect::<std::io::Result<_>>()?;
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rust_files(root, &path, out)?;
        } else if path.extension().is_some_and(|e| e == "rs") {
            let name = path
                .strip_prefix(root)
                .map_err(std::io::Error::other)?
                .to_string_lossy()
                .replace('\\', "/");
            out.push(Source {
                name,
                text: std::fs::read_to_string(&path)?,
            });
        }
    }
    Ok(())
}

fn workspace_graph() -> Graph {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut sources = Vec::new();
    for dir in ["engine/src", "game/src"] {
        rust_files(&root, &root.join(dir), &mut sources).expect("read the sources");
    }
    assert!(
        sources.len() > 50,
        "only {} source files found",
        sources.len()
    );
    graph(&sources)
}

#[test]
fn no_file_is_part_of_an_import_cycle() {
    let g = workspace_graph();
    let found = cycles(&g);
    let text: Vec<String> = found.iter().map(|c| describe(&g, c)).collect();
    for t in &text {
        println!("{t}");
    }
    assert!(
        found.is_empty(),
        "{} import cycles between files:\n  {}",
        found.len(),
        text.join("\n  ")
    );
}

#[test]
fn no_two_sibling_modules_depend_on_each_other() {
    let g = sibling_graph(&workspace_graph());
    // Cycles of files alone are the test above's.
    let found: Vec<Vec<usize>> = cycles(&g)
        .into_iter()
        .filter(|c| c.iter().any(|&m| !g.names[m].ends_with(".rs")))
        .collect();
    let text: Vec<String> = found.iter().map(|c| describe(&g, c)).collect();
    for t in &text {
        println!("{t}");
    }
    assert!(
        found.is_empty(),
        "{} import cycles between modules:\n  {}",
        found.len(),
        text.join("\n  ")
    );
}

#[test]
fn the_layers_below_the_renderer_import_nothing_from_it() {
    let g = workspace_graph();
    let mut violations = Vec::new();
    for (from, targets) in g.edges.iter().enumerate() {
        if !BELOW_RENDER.iter().any(|p| g.names[from].starts_with(p)) {
            continue;
        }
        for (&to, (at, path)) in targets {
            if g.names[to].starts_with(RENDER) {
                violations.push(format!("{at}: {path}"));
            }
        }
    }
    let checked = g
        .names
        .iter()
        .filter(|n| BELOW_RENDER.iter().any(|p| n.starts_with(p)))
        .count();
    assert!(
        checked >= 10,
        "only {checked} files below the renderer found"
    );
    assert!(
        violations.is_empty(),
        "{} imports into {RENDER} from below it:\n  {}",
        violations.len(),
        violations.join("\n  ")
    );
}

#[cfg(test)]
mod parser {
    use super::*;

    fn graph_of(files: &[(&str, &str)]) -> Graph {
        let sources: Vec<Source> = files
            .iter()
            .map(|(name, text)| Source {
                name: (*name).into(),
                text: (*text).into(),
            })
            .collect();
        graph(&sources)
    }

    fn edges(g: &Graph) -> Vec<(String, String)> {
        let mut out = Vec::new();
        for (from, targets) in g.edges.iter().enumerate() {
            for to in targets.keys() {
                out.push((g.names[from].clone(), g.names[*to].clone()));
            }
        }
        out.sort();
        out
    }

    fn edge(a: &str, b: &str) -> (String, String) {
        (a.into(), b.into())
    }

    #[test]
    fn an_exported_macro_belongs_to_the_file_that_defines_it() {
        let g = graph_of(&[
            (
                "engine/src/lib.rs",
                "pub mod choice;\npub mod brdf;\npub use brdf::Model;\n",
            ),
            (
                "engine/src/choice.rs",
                "#[doc(hidden)]\n#[macro_export]\nmacro_rules! __choices { () => {} }\npub use crate::__choices as choices;\n",
            ),
            (
                "engine/src/shading/brdf.rs",
                "crate::choice::choices! {}\npub struct Model;\n",
            ),
        ]);
        let edges = edges(&g);
        let brdf =
            |to: &str| edges.contains(&("engine/src/shading/brdf.rs".to_string(), to.to_string()));
        assert!(
            brdf("engine/src/choice.rs") && !brdf("engine/src/lib.rs"),
            "{edges:?}"
        );
    }

    #[test]
    fn a_two_file_cycle_is_found() {
        let g = graph_of(&[
            ("engine/src/lib.rs", "pub mod a;\npub mod b;\n"),
            (
                "engine/src/a.rs",
                "use crate::b::{Bee, other};\npub struct A;\n",
            ),
            (
                "engine/src/b.rs",
                "pub struct Bee;\npub fn other() -> usize { crate::a::SIZE }\n",
            ),
        ]);
        let found = cycles(&g);
        assert_eq!(found.len(), 1);
        assert_eq!(
            describe(&g, &found[0]).lines().next(),
            Some("engine/src/a.rs -> engine/src/b.rs -> engine/src/a.rs")
        );
        assert!(describe(&g, &found[0]).contains("engine/src/b.rs:2: crate::a::SIZE"));
    }

    #[test]
    fn a_mod_declaration_is_not_an_edge_and_a_parent_item_is() {
        let g = graph_of(&[
            ("engine/src/lib.rs", "pub mod render;\n"),
            (
                "engine/src/render/mod.rs",
                "pub mod plan;\nmod pass;\npub struct Schedule;\n",
            ),
            ("engine/src/render/plan.rs", "pub struct Plan;\n"),
            (
                "engine/src/render/pass.rs",
                "use super::Schedule;\nfn f() { let _ = super::plan::Plan; }\n",
            ),
        ]);
        assert_eq!(
            edges(&g),
            [
                edge("engine/src/render/pass.rs", "engine/src/render/mod.rs"),
                edge("engine/src/render/pass.rs", "engine/src/render/plan.rs"),
            ]
        );
        assert!(cycles(&g).is_empty());
    }

    #[test]
    fn paths_in_comments_and_literals_are_ignored() {
        let g = graph_of(&[
            ("engine/src/lib.rs", "pub mod a;\npub mod b;\n"),
            (
                "engine/src/a.rs",
                concat!(
                    "// use crate::b::B;\n",
                    "/* crate::b::B /* nested */ crate::b::B */\n",
                    "/// [`crate::b::B`]\n",
                    "const S: &str = \"crate::b::B \\\" crate::b::B\";\n",
                    "const R: &str = r#\"crate::b::B \" crate::b::B\"#;\n",
                    "const Q: char = '\"'; fn f<'a>(x: &'a str) -> &'a str { x }\n",
                    "pub struct A;\n",
                ),
            ),
            ("engine/src/b.rs", "use crate::a::A;\npub struct B;\n"),
        ]);
        assert_eq!(edges(&g), [edge("engine/src/b.rs", "engine/src/a.rs")]);
    }

    #[test]
    fn re_exports_resolve_to_the_defining_file() {
        let g = graph_of(&[
            (
                "engine/src/lib.rs",
                "pub mod scene;\npub use scene::Camera as Cam;\n",
            ),
            (
                "engine/src/scene/mod.rs",
                "pub mod camera;\npub mod light;\npub use camera::Camera;\n",
            ),
            ("engine/src/scene/camera.rs", "pub struct Camera;\n"),
            (
                "engine/src/scene/light.rs",
                "use crate::scene::Camera;\nfn f() -> crate::Cam { crate::scene::Camera::default() }\n",
            ),
        ]);
        assert_eq!(
            edges(&g),
            [
                edge("engine/src/lib.rs", "engine/src/scene/camera.rs"),
                edge("engine/src/scene/light.rs", "engine/src/scene/camera.rs"),
                edge("engine/src/scene/mod.rs", "engine/src/scene/camera.rs"),
            ]
        );
    }

    #[test]
    fn super_in_an_inline_module_is_its_file_and_main_sees_the_library() {
        let g = graph_of(&[
            ("game/src/lib.rs", "pub mod view;\n"),
            (
                "game/src/view.rs",
                "pub fn run() {}\n#[cfg(test)]\nmod tests {\n    use super::*;\n}\n",
            ),
            (
                "game/src/main.rs",
                "use lumen_game::view;\nfn main() { view::run() }\n",
            ),
        ]);
        assert_eq!(edges(&g), [edge("game/src/main.rs", "game/src/view.rs")]);
    }

    #[test]
    fn sibling_folders_that_use_each_other_are_a_module_cycle() {
        let g = graph_of(&[
            ("game/src/lib.rs", "pub mod bench;\npub mod view;\n"),
            (
                "game/src/bench/mod.rs",
                "pub mod report;\nfn f() { crate::view::run() }\n",
            ),
            ("game/src/bench/report.rs", "pub struct Sample;\n"),
            (
                "game/src/view/mod.rs",
                "use crate::bench::report::Sample;\npub fn run() {}\n",
            ),
        ]);
        assert!(cycles(&g).is_empty());
        let modules = sibling_graph(&g);
        let found = cycles(&modules);
        assert_eq!(found.len(), 1);
        assert_eq!(
            describe(&modules, &found[0]),
            "game/src/bench -> game/src/view -> game/src/bench\n    \
             game/src/bench/mod.rs:2: crate::view::run\n    \
             game/src/view/mod.rs:1: crate::bench::report::Sample"
        );
    }

    #[test]
    fn module_paths_of_files() {
        let m = |n: &str| module_of(n).map(|(m, _)| m);
        let p =
            |k: &str, s: &[&str]| Some((k.to_string(), s.iter().map(|s| s.to_string()).collect()));
        assert_eq!(m("engine/src/lib.rs"), p("lumen", &[]));
        assert_eq!(m("engine/src/render/mod.rs"), p("lumen", &["render"]));
        assert_eq!(
            m("engine/src/render/shadow/pass.rs"),
            p("lumen", &["render", "shadow", "pass"])
        );
        assert_eq!(m("game/src/lib.rs"), p("lumen_game", &[]));
        assert_eq!(m("game/src/main.rs"), p("lumen (bin)", &[]));
        assert_eq!(m("tests/render.rs"), None);
    }
}
