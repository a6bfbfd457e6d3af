//! The house's own rules, checked on every test run (a package of its own, so that
//! `cargo test -p house` builds in seconds, without wgpu):
//!
//! - no module of any crate imports itself around a loop (issue 31, house rule 13: each module can
//!   be read and changed alone). Every `src/**/*.rs` file is parsed with `syn`, so brace groups,
//!   `self`, `super::super`, renames, globs, re-exports, paths in code and in macro arguments all
//!   count; a module using its own ancestors (its parent's items) is allowed;
//! - each crate depends only on the crates below it ([`LAYERS`]), in its manifest and in its code;
//! - every `tests/*.rs` file is registered, so none is silently left out of `cargo test`, and the
//!   README shows the test command CI runs;
//! - no function outside tests is over [`MAX_FUNCTION_LINES`] lines (house rule: a function is
//!   read whole).

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt;
use std::path::{Component, Path, PathBuf};

use proc_macro2::{Delimiter, Spacing, TokenStream, TokenTree};
use syn::parse::Parser;
use syn::punctuated::Punctuated;
use syn::visit::{self, Visit};
use syn::{Attribute, Ident, ImplItem, Item, Meta, Token, UseTree};

/// What a crate may depend on among the workspace's crates.
enum May {
    Only(&'static [&'static str]),
    Anything,
}

/// The layers, bottom up (ARCHITECTURE.md's "Layers"): each workspace crate, by package name, and
/// the workspace crates it may depend on, checked in its manifest's `[dependencies]` and in the
/// paths of its code. A crate named here but not in the workspace is skipped; a workspace crate
/// missing here fails the check.
const LAYERS: &[(&str, May)] = &[
    ("mc", May::Only(&[])),
    ("fit", May::Only(&["mc"])),
    ("shading", May::Only(&["mc", "fit"])),
    ("gpu", May::Only(&["fit", "shading"])),
    ("mc_gpu", May::Only(&["mc", "fit", "shading", "gpu"])),
    ("render", May::Only(&["mc", "fit", "shading", "gpu"])),
    (
        "report",
        May::Only(&["mc", "fit", "shading", "gpu", "mc_gpu"]),
    ),
    (
        "sss-cli",
        May::Only(&["mc", "fit", "shading", "gpu", "mc_gpu", "render", "report"]),
    ),
    (
        "sss-python",
        May::Only(&["mc", "fit", "shading", "gpu", "render"]),
    ),
    ("sss-benches", May::Anything),
    ("house", May::Only(&[])),
    ("testkit", May::Only(&[])),
];

/// The workspace root, `..` resolved.
fn root() -> PathBuf {
    lexical(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
}

/// `path` with its `.` and `..` resolved without the disk (a registered file may be absent).
fn lexical(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// What a file names

/// A module's path inside its crate: `["analytic", "burley"]`; the crate root is `[]`.
type Module = Vec<String>;

/// A module as printed: `analytic::burley`, the root `crate`.
fn show(m: &[String]) -> String {
    if m.is_empty() {
        "crate".into()
    } else {
        m.join("::")
    }
}

/// The module a file under `src/` holds: `analytic/burley.rs` is `analytic::burley`; `mod.rs`,
/// `lib.rs` and `main.rs` hold their folder's.
fn module_of(file: &Path) -> Module {
    let mut m: Module = file
        .with_extension("")
        .iter()
        .map(|s| s.to_string_lossy().into_owned())
        .collect();
    if m.last()
        .is_some_and(|l| ["mod", "lib", "main"].contains(&l.as_str()))
    {
        m.pop();
    }
    m
}

/// A path as a file writes it, with the inline modules around it: `super::a::X` inside
/// `mod width { … }` is `scope: ["width"], segments: ["super", "a", "X"]`.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Named {
    scope: Vec<String>,
    /// Written with a leading `::` (a crate's name follows).
    global: bool,
    segments: Vec<String>,
}

impl fmt::Display for Named {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let lead = if self.global { "::" } else { "" };
        write!(f, "{lead}{}", self.segments.join("::"))
    }
}

/// What one file names outside its `#[cfg(test)]` items.
#[derive(Debug, Default)]
struct Names {
    /// Every leaf of its `use` trees, and every path of two segments or more in its code and in
    /// its macros' arguments.
    paths: BTreeSet<Named>,
    /// Names its `use crate::…`, `use super::…` and `use self::…` bring into scope, which then are
    /// not the crates of the same name (`use crate::tables as mc;`).
    local_names: BTreeSet<String>,
    /// Its `#[cfg(test)] mod x;` declarations (scope and name): files of tests, not of the crate.
    test_mods: Vec<Vec<String>>,
    /// Its `mod` items with a `#[path]`, which the file-based module map would misplace.
    moved_mods: Vec<String>,
}

/// Parses one file and reads what it names.
fn names_in(text: &str) -> syn::Result<Names> {
    let file = syn::parse_file(text)?;
    let mut reader = Reader::default();
    reader.visit_file(&file);
    Ok(reader.names)
}

/// Walks a file's syntax tree, collecting its [`Names`].
#[derive(Default)]
struct Reader {
    names: Names,
    /// The inline modules (`mod width { … }`) around the node being read.
    scope: Vec<String>,
}

impl Reader {
    fn push(&mut self, global: bool, segments: Vec<String>) {
        let scope = self.scope.clone();
        self.names.paths.insert(Named {
            scope,
            global,
            segments,
        });
    }
}

impl<'ast> Visit<'ast> for Reader {
    fn visit_item(&mut self, item: &'ast Item) {
        if !test_only(item_attrs(item)) {
            visit::visit_item(self, item);
        } else if let Item::Mod(m) = item
            && m.content.is_none()
        {
            let path = [self.scope.clone(), vec![m.ident.to_string()]].concat();
            self.names.test_mods.push(path);
        }
    }

    fn visit_impl_item(&mut self, item: &'ast ImplItem) {
        if !test_only(impl_item_attrs(item)) {
            visit::visit_impl_item(self, item);
        }
    }

    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        if m.attrs.iter().any(|a| a.path().is_ident("path")) {
            self.names.moved_mods.push(m.ident.to_string());
        }
        let inline = m.content.is_some();
        if inline {
            self.scope.push(m.ident.to_string());
        }
        visit::visit_item_mod(self, m);
        if inline {
            self.scope.pop();
        }
    }

    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        use_tree(&u.tree, &mut Vec::new(), u.leading_colon.is_some(), self);
    }

    fn visit_path(&mut self, p: &'ast syn::Path) {
        if p.segments.len() >= 2 || p.leading_colon.is_some() {
            let segments = p.segments.iter().map(|s| s.ident.to_string()).collect();
            self.push(p.leading_colon.is_some(), segments);
        }
        visit::visit_path(self, p);
    }

    fn visit_macro(&mut self, m: &'ast syn::Macro) {
        visit::visit_macro(self, m);
        paths_in_tokens(m.tokens.clone(), self);
    }
}

/// Whether `attrs` compile their item for tests only: `#[cfg(test)]` or `#[cfg(all(test, …))]`.
fn test_only(attrs: &[Attribute]) -> bool {
    fn needs_test(meta: &Meta) -> bool {
        match meta {
            Meta::Path(p) => p.is_ident("test"),
            Meta::List(l) if l.path.is_ident("all") => l
                .parse_args_with(Punctuated::<Meta, Token![,]>::parse_terminated)
                .is_ok_and(|all| all.iter().any(needs_test)),
            _ => false,
        }
    }
    attrs
        .iter()
        .any(|a| a.path().is_ident("cfg") && a.parse_args::<Meta>().is_ok_and(|m| needs_test(&m)))
}

/// An item's attributes (none for verbatim tokens).
fn item_attrs(item: &Item) -> &[Attribute] {
    match item {
        Item::Const(i) => &i.attrs,
        Item::Enum(i) => &i.attrs,
        Item::ExternCrate(i) => &i.attrs,
        Item::Fn(i) => &i.attrs,
        Item::ForeignMod(i) => &i.attrs,
        Item::Impl(i) => &i.attrs,
        Item::Macro(i) => &i.attrs,
        Item::Mod(i) => &i.attrs,
        Item::Static(i) => &i.attrs,
        Item::Struct(i) => &i.attrs,
        Item::Trait(i) => &i.attrs,
        Item::TraitAlias(i) => &i.attrs,
        Item::Type(i) => &i.attrs,
        Item::Union(i) => &i.attrs,
        Item::Use(i) => &i.attrs,
        _ => &[],
    }
}

/// An associated item's attributes (none for verbatim tokens).
fn impl_item_attrs(item: &ImplItem) -> &[Attribute] {
    match item {
        ImplItem::Const(i) => &i.attrs,
        ImplItem::Fn(i) => &i.attrs,
        ImplItem::Type(i) => &i.attrs,
        ImplItem::Macro(i) => &i.attrs,
        _ => &[],
    }
}

/// Records each leaf of a `use` tree as a path: `use crate::a::{self, b::C as D, e::*};` names
/// `crate::a`, `crate::a::b::C` and `crate::a::e`.
fn use_tree(tree: &UseTree, prefix: &mut Vec<String>, global: bool, reader: &mut Reader) {
    match tree {
        UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            use_tree(&p.tree, prefix, global, reader);
            prefix.pop();
        }
        UseTree::Name(n) => use_leaf(prefix, &n.ident, &n.ident, global, reader),
        UseTree::Rename(r) => use_leaf(prefix, &r.ident, &r.rename, global, reader),
        UseTree::Glob(_) => reader.push(global, prefix.clone()),
        UseTree::Group(g) => {
            for t in &g.items {
                use_tree(t, prefix, global, reader);
            }
        }
    }
}

/// Records `prefix::ident` (`prefix` itself for `self`), brought into scope as `bound`.
fn use_leaf(prefix: &[String], ident: &Ident, bound: &Ident, global: bool, reader: &mut Reader) {
    let mut path = prefix.to_vec();
    if ident != "self" {
        path.push(ident.to_string());
    }
    // `use crate::a::{self}` brings `a` into scope, `use crate::a::{self as b}` brings `b`.
    let bound = match bound.to_string() {
        b if b == "self" => path.last().cloned().unwrap_or_default(),
        b => b,
    };
    let local = matches!(
        path.first().map(String::as_str),
        Some("crate" | "super" | "self")
    );
    if local && !global {
        reader.names.local_names.insert(bound);
    }
    reader.push(global, path);
}

/// Records the paths in a macro's tokens, which `syn` leaves unparsed (`format!("{}",
/// crate::a::NAME)`, a `macro_rules!` body's `$crate::a::f`): each run `x::y::z`, and a brace
/// group after `x::` read as a `use` group.
fn paths_in_tokens(tokens: TokenStream, reader: &mut Reader) {
    let tt: Vec<TokenTree> = tokens.into_iter().collect();
    let mut i = 0;
    while i < tt.len() {
        match &tt[i] {
            TokenTree::Group(g) => {
                paths_in_tokens(g.stream(), reader);
                i += 1;
            }
            TokenTree::Ident(_) if !(i >= 2 && is_colon2(&tt, i - 2)) => {
                i = token_path(&tt, i, reader);
            }
            _ => i += 1,
        }
    }
}

/// Whether `tt[i]` and `tt[i + 1]` are `::`.
fn is_colon2(tt: &[TokenTree], i: usize) -> bool {
    let colon = |t: Option<&TokenTree>, spacing: Option<Spacing>| {
        matches!(t, Some(TokenTree::Punct(p))
            if p.as_char() == ':' && spacing.is_none_or(|s| p.spacing() == s))
    };
    colon(tt.get(i), Some(Spacing::Joint)) && colon(tt.get(i + 1), None)
}

/// Reads the path that starts at the identifier `tt[start]` and returns the index after it.
fn token_path(tt: &[TokenTree], start: usize, reader: &mut Reader) -> usize {
    let mut segments = vec![tt[start].to_string()];
    let mut i = start + 1;
    while is_colon2(tt, i) {
        match tt.get(i + 2) {
            Some(TokenTree::Ident(id)) => segments.push(id.to_string()),
            Some(TokenTree::Group(g)) if g.delimiter() == Delimiter::Brace => {
                let items = Punctuated::<UseTree, Token![,]>::parse_terminated;
                match items.parse2(g.stream()) {
                    Ok(items) => items
                        .iter()
                        .for_each(|t| use_tree(t, &mut segments.clone(), false, reader)),
                    Err(_) => paths_in_tokens(g.stream(), reader),
                }
                return i + 3;
            }
            _ => break,
        }
        i += 3;
    }
    if segments.len() >= 2 {
        reader.push(false, segments);
    }
    i
}

// ---------------------------------------------------------------------------------------------
// Where a path leads

/// Where a path leads from a file.
#[derive(Debug, PartialEq)]
enum Target {
    /// Into the same crate: an absolute path, not yet cut to its module.
    Local(Vec<String>),
    /// Outside the crate's modules: the first segment, another crate's name or a name in scope
    /// (`std`, `Vec`, an enum).
    Outside(String),
}

/// Resolves `named`, written in the file of `module`, as Rust does, given the crate's modules and
/// the file's [`Names::local_names`].
fn resolve(
    named: &Named,
    module: &[String],
    modules: &BTreeSet<Module>,
    local_names: &BTreeSet<String>,
) -> Option<Target> {
    let here: Vec<String> = module.iter().chain(&named.scope).cloned().collect();
    let (first, rest) = named.segments.split_first()?;
    if named.global {
        return Some(Target::Outside(first.clone()));
    }
    match first.as_str() {
        "crate" => Some(Target::Local(rest.to_vec())),
        "self" => Some(Target::Local([&here[..], rest].concat())),
        "super" => {
            let ups = named.segments.iter().take_while(|s| *s == "super").count();
            let base = here.len().checked_sub(ups)?;
            Some(Target::Local(
                [&here[..base], &named.segments[ups..]].concat(),
            ))
        }
        _ if modules.contains(&[&here[..], std::slice::from_ref(first)].concat()) => {
            Some(Target::Local([&here[..], &named.segments[..]].concat()))
        }
        _ if local_names.contains(first) => None,
        _ => Some(Target::Outside(first.clone())),
    }
}

/// The module that holds `path`: its longest prefix that is a module (an item belongs to its
/// module's file, and so does an inline module).
fn holder(path: &[String], modules: &BTreeSet<Module>) -> Option<Module> {
    (0..=path.len())
        .rev()
        .map(|k| path[..k].to_vec())
        .find(|m| modules.contains(m))
}

/// What each module of a crate names, from its files (path under `src/`, text); modules declared
/// `#[cfg(test)] mod x;` are left out with everything below them.
fn parse_crate(files: &[(PathBuf, String)]) -> BTreeMap<Module, Names> {
    let mut names: BTreeMap<Module, Names> = files
        .iter()
        .map(|(file, text)| {
            let n = names_in(text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            (module_of(file), n)
        })
        .collect();
    let tests: Vec<Module> = names
        .iter()
        .flat_map(|(m, n)| n.test_mods.iter().map(move |t| [&m[..], t].concat()))
        .collect();
    names.retain(|m, _| !tests.iter().any(|t| m.starts_with(t)));
    names
}

// ---------------------------------------------------------------------------------------------
// Module circles

/// Module → the modules of its crate it names, each with the first path that names it; a module's
/// own ancestors are left out (a child may use its parent's items, `crate::parse_count` included).
type Graph = BTreeMap<Module, BTreeMap<Module, String>>;

/// The module graph of a crate.
fn module_graph(names: &BTreeMap<Module, Names>) -> Graph {
    let modules: BTreeSet<Module> = names.keys().cloned().collect();
    let mut graph = Graph::new();
    for (m, n) in names {
        let to = graph.entry(m.clone()).or_default();
        for named in &n.paths {
            let Some(Target::Local(path)) = resolve(named, m, &modules, &n.local_names) else {
                continue;
            };
            match holder(&path, &modules) {
                Some(t) if !m.starts_with(&t) => {
                    to.entry(t).or_insert_with(|| named.to_string());
                }
                _ => {}
            }
        }
    }
    graph
}

/// The strongly connected components of more than one module (Tarjan), each sorted.
fn circles(g: &Graph) -> Vec<BTreeSet<Module>> {
    struct State<'a> {
        g: &'a Graph,
        index: BTreeMap<&'a Module, usize>,
        low: BTreeMap<&'a Module, usize>,
        stack: Vec<&'a Module>,
        out: Vec<BTreeSet<Module>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a Module) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        for w in s.g[v].keys() {
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                s.low.insert(v, s.low[v].min(lw));
            } else if s.stack.contains(&w) {
                let iw = s.index[w];
                s.low.insert(v, s.low[v].min(iw));
            }
        }
        if s.low[v] == s.index[v] {
            let mut c = BTreeSet::new();
            while let Some(w) = s.stack.pop() {
                c.insert(w.clone());
                if w == v {
                    break;
                }
            }
            if c.len() > 1 {
                s.out.push(c);
            }
        }
    }
    let mut s = State {
        g,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: vec![],
        out: vec![],
    };
    for v in g.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

/// One loop around `circle`, from its first module back to it (breadth-first, inside the circle).
fn a_loop(circle: &BTreeSet<Module>, g: &Graph) -> Vec<Module> {
    let start = circle.first().expect("a circle has modules");
    let mut came_from: BTreeMap<&Module, &Module> = BTreeMap::new();
    let mut queue = VecDeque::from([start]);
    while let Some(v) = queue.pop_front() {
        for w in g[v].keys().filter(|w| circle.contains(*w)) {
            if w == start {
                let mut path = vec![start.clone(), v.clone()];
                let mut at = v;
                while let Some(&back) = came_from.get(at) {
                    path.push(back.clone());
                    at = back;
                }
                path.reverse();
                return path;
            }
            if !came_from.contains_key(w) {
                came_from.insert(w, v);
                queue.push_back(w);
            }
        }
    }
    unreachable!("a strongly connected component has a loop through each module")
}

/// A circle as the test prints it: its modules, one loop with the path that makes each step, e.g.
/// `simulate, table: simulate -> table (crate::table::merge) -> simulate (crate::simulate)`.
fn describe(circle: &BTreeSet<Module>, g: &Graph) -> String {
    let members: Vec<String> = circle.iter().map(|m| show(m)).collect();
    let path = a_loop(circle, g);
    let mut text = format!("{}: {}", members.join(", "), show(&path[0]));
    for step in path.windows(2) {
        text += &format!(" -> {} ({})", show(&step[1]), g[&step[0]][&step[1]]);
    }
    text
}

// ---------------------------------------------------------------------------------------------
// The workspace

/// A workspace member, as its manifest describes it.
struct Member {
    /// Its folder, relative to the workspace root (`crates/gpu`).
    dir: String,
    package: String,
    /// The name its code is used by: `[lib] name`, else the package's with `_` for `-`.
    lib: String,
    /// The packages of its `[dependencies]`, build and target-specific ones included.
    deps: BTreeSet<String>,
    /// Its `[[test]]` targets' paths, relative to its folder.
    tests: Vec<String>,
}

/// A TOML file of the workspace, parsed.
fn read_toml(path: &Path) -> toml::Table {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The workspace's members, from the root manifest's `members`, each read from its manifest.
fn members() -> Vec<Member> {
    let workspace = read_toml(&root().join("Cargo.toml"));
    let dirs = workspace["workspace"]["members"]
        .as_array()
        .expect("workspace.members");
    dirs.iter()
        .map(|d| member(d.as_str().expect("a member's folder")))
        .collect()
}

/// The member in folder `dir`.
fn member(dir: &str) -> Member {
    let manifest = read_toml(&root().join(dir).join("Cargo.toml"));
    let package = manifest["package"]["name"]
        .as_str()
        .expect("package.name")
        .to_string();
    let lib = manifest
        .get("lib")
        .and_then(|l| l.get("name"))
        .and_then(|n| n.as_str())
        .map_or_else(|| package.replace('-', "_"), str::to_string);
    let tests = manifest
        .get("test")
        .and_then(|t| t.as_array())
        .into_iter()
        .flatten()
        .filter_map(|t| t.get("path")?.as_str().map(str::to_string))
        .collect();
    let deps = dependency_packages(&manifest);
    Member {
        dir: dir.to_string(),
        package,
        lib,
        deps,
        tests,
    }
}

/// The packages a manifest depends on outside tests: `[dependencies]`, `[build-dependencies]` and
/// their `[target.'…'.…]` forms, by package name (a `package = "…"` rename followed).
fn dependency_packages(manifest: &toml::Table) -> BTreeSet<String> {
    let sections = ["dependencies", "build-dependencies"];
    let targets = manifest
        .get("target")
        .and_then(|t| t.as_table())
        .into_iter()
        .flatten();
    let tables = std::iter::once(manifest)
        .chain(targets.filter_map(|(_, t)| t.as_table()))
        .flat_map(|t| sections.iter().filter_map(|s| t.get(*s)?.as_table()));
    let mut out = BTreeSet::new();
    for table in tables {
        for (key, spec) in table {
            let renamed = spec.get("package").and_then(|p| p.as_str());
            out.insert(renamed.unwrap_or(key).to_string());
        }
    }
    out
}

/// What every module of `member` names, read from its `src/`.
fn member_names(member: &Member) -> BTreeMap<Module, Names> {
    parse_crate(&source_files(member))
}

/// Every `.rs` file below `member`'s `src/`, by its path there, with its text.
fn source_files(member: &Member) -> Vec<(PathBuf, String)> {
    let src = root().join(&member.dir).join("src");
    let mut files = Vec::new();
    let mut dirs = vec![src.clone()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let p = entry.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&p).unwrap();
                files.push((p.strip_prefix(&src).unwrap().to_path_buf(), text));
            }
        }
    }
    files
}

// ---------------------------------------------------------------------------------------------
// Layers

/// Whether the crate `package` may depend on the workspace crate `dep`; `None` for a crate that
/// [`LAYERS`] does not list.
fn may_depend(package: &str, dep: &str) -> Option<bool> {
    let (_, may) = LAYERS.iter().find(|(p, _)| *p == package)?;
    Some(match may {
        May::Only(deps) => deps.contains(&dep),
        May::Anything => true,
    })
}

/// A dependency across the layers: `krate` on `dep`, seen in `place`.
struct Breach {
    krate: String,
    dep: String,
    place: String,
}

impl fmt::Display for Breach {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{} depends on {}: {}", self.krate, self.dep, self.place)
    }
}

/// The manifests' dependencies that [`LAYERS`] does not allow.
fn manifest_breaches(members: &[Member]) -> Vec<Breach> {
    let packages: BTreeSet<&str> = members.iter().map(|m| m.package.as_str()).collect();
    let mut out = Vec::new();
    for m in members {
        for dep in m.deps.iter().filter(|d| packages.contains(d.as_str())) {
            if may_depend(&m.package, dep) == Some(false) {
                let place = format!("{}/Cargo.toml", m.dir);
                out.push(Breach {
                    krate: m.package.clone(),
                    dep: dep.clone(),
                    place,
                });
            }
        }
    }
    out
}

/// The workspace crates each module of `names` uses in its code (by the crates' `lib` names in
/// `libs`), with the first path that names each.
fn crates_used(
    names: &BTreeMap<Module, Names>,
    libs: &BTreeMap<&str, &str>,
) -> Vec<(Module, String, String)> {
    let modules: BTreeSet<Module> = names.keys().cloned().collect();
    let mut out = Vec::new();
    for (m, n) in names {
        let mut seen = BTreeSet::new();
        for named in &n.paths {
            if let Some(Target::Outside(first)) = resolve(named, m, &modules, &n.local_names)
                && let Some(package) = libs.get(first.as_str())
                && seen.insert(*package)
            {
                out.push((m.clone(), package.to_string(), named.to_string()));
            }
        }
    }
    out
}

/// The paths in the crates' code that name a crate [`LAYERS`] does not allow.
fn code_breaches(members: &[Member]) -> Vec<Breach> {
    let libs: BTreeMap<&str, &str> = members
        .iter()
        .map(|m| (m.lib.as_str(), m.package.as_str()))
        .collect();
    let mut out = Vec::new();
    for m in members {
        for (module, dep, path) in crates_used(&member_names(m), &libs) {
            if dep != m.package && may_depend(&m.package, &dep) == Some(false) {
                let place = format!("{} module {} names {path}", m.dir, show(&module));
                out.push(Breach {
                    krate: m.package.clone(),
                    dep,
                    place,
                });
            }
        }
    }
    out
}

/// Every breach of [`LAYERS`], in the manifests and in the code.
fn breaches(members: &[Member]) -> Vec<Breach> {
    let mut all = manifest_breaches(members);
    all.extend(code_breaches(members));
    all
}

// ---------------------------------------------------------------------------------------------
// The workspace's tests

#[test]
fn no_crate_has_a_module_cycle() {
    let members = members();
    assert!(
        members.len() >= 7,
        "found {} workspace members",
        members.len()
    );
    let mut found = Vec::new();
    for m in &members {
        let g = module_graph(&member_names(m));
        found.extend(
            circles(&g)
                .iter()
                .map(|c| format!("{}: {}", m.dir, describe(c, &g))),
        );
    }
    assert!(
        found.is_empty(),
        "module import circles:\n{}",
        found.join("\n")
    );
}

/// The module map assumes each file sits where its module path says: no `#[path]` on a `mod`.
/// The command line's shared modules: what every command may use. Every other top-level module
/// of `crates/cli/src` is a command (it parses, calls the libraries and prints) and never uses
/// another command; `main.rs` dispatches to them.
const CLI_SHARED: &[&str] = &["common", "files", "library", "cache"];

/// The command-line modules that use another command, as printed (`simulate uses table`).
fn command_imports(g: &Graph) -> Vec<String> {
    let mut found = Vec::new();
    for (m, to) in g {
        let Some(own) = m.first() else { continue };
        for (t, path) in to {
            match t.first() {
                Some(top) if top != own && !CLI_SHARED.contains(&top.as_str()) => {
                    found.push(format!("{} uses {} ({path})", show(m), show(t)))
                }
                _ => {}
            }
        }
    }
    found
}

#[test]
fn no_command_imports_another() {
    let cli = members()
        .into_iter()
        .find(|m| m.package == "sss-cli")
        .expect("the sss-cli member");
    let found = command_imports(&module_graph(&member_names(&cli)));
    assert!(
        found.is_empty(),
        "commands using commands:\n{}",
        found.join("\n")
    );
    // The check can fail: a render that reached into fit's command is found.
    let g = graph_of(&[
        ("main.rs", "mod fit; mod render; mod common;"),
        ("fit.rs", "pub fn build() {}"),
        ("common.rs", "pub fn bar() {}"),
        (
            "render.rs",
            "use crate::common::bar; use crate::fit::build;",
        ),
    ]);
    assert_eq!(command_imports(&g), ["render uses fit (crate::fit::build)"]);
}

/// The CLI is glue: flags, their mapping onto library requests, and printing (ARCHITECTURE.md,
/// Known exceptions). What a command computes, runs or formats belongs in a library, and this
/// bound keeps it there.
#[test]
fn the_cli_is_at_most_2500_lines() {
    let cli = member("crates/cli");
    let lines: usize = source_files(&cli)
        .iter()
        .map(|(_, t)| t.lines().count())
        .sum();
    assert!(
        lines > 1000,
        "the CLI's sources were not read ({lines} lines)"
    );
    assert!(
        lines <= 2500,
        "crates/cli/src has {lines} lines (at most 2,500)"
    );
}

/// ARCHITECTURE.md is read whole by whoever changes the code: at most 250 lines, and every path
/// it names inside the repository (nothing above the root, `../`).
#[test]
fn the_architecture_page_is_short_and_points_inside() {
    let text = short_doc("ARCHITECTURE.md", 250);
    let outside: Vec<&str> = text.lines().filter(|l| l.contains("../")).collect();
    assert!(
        outside.is_empty(),
        "paths outside the repository: {outside:?}"
    );
}

/// The text of the page at `path` (from the root), which must have more than 100 lines (it was
/// read) and at most `max`.
fn short_doc(path: &str, max: usize) -> String {
    let text = std::fs::read_to_string(root().join(path)).unwrap();
    let lines = text.lines().count();
    assert!(lines > 100, "{path} was not read ({lines} lines)");
    assert!(lines <= max, "{path} has {lines} lines (at most {max})");
    text
}

/// Every test file `.ci/run` names exists (a comment naming a file that was renamed misleads
/// whoever reads why a package is installed).
#[test]
fn the_ci_script_names_only_test_files_that_exist() {
    let text = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    let named: Vec<&str> = text
        .split(|c: char| c.is_whitespace() || "();,".contains(c))
        .filter(|w| w.contains("tests/") && w.ends_with(".rs"))
        .collect();
    assert!(named.len() >= 5, "named: {named:?}");
    let missing: Vec<&&str> = named.iter().filter(|p| !root().join(p).exists()).collect();
    assert!(
        missing.is_empty(),
        ".ci/run names missing files: {missing:?}"
    );
}

/// docs/measurements.md is a reference a reader searches: at most 600 lines, its first section
/// the table of where every figure stands.
#[test]
fn the_measurements_page_is_short_and_starts_with_its_table() {
    let text = short_doc("docs/measurements.md", 600);
    let first = text
        .lines()
        .find(|l| l.starts_with("## "))
        .unwrap_or_default();
    assert_eq!(first, "## Where every figure stands", "the first section");
    let table = text
        .split("## Where every figure stands")
        .nth(1)
        .unwrap_or_default();
    assert!(
        table
            .trim_start()
            .starts_with("| area | figure | command | date |"),
        "the first section is the table of figures"
    );
}

/// The most lines a function outside tests may span, from `fn` to its closing brace.
const MAX_FUNCTION_LINES: usize = 150;

/// The lines [first `fn`, closing brace] of every function outside test code in one file.
#[derive(Default)]
struct Functions(Vec<(String, usize)>);

impl Functions {
    fn add(&mut self, name: &Ident, sig: &syn::Signature, block: &syn::Block) {
        let first = sig.fn_token.span.start().line;
        let last = block.brace_token.span.close().end().line;
        self.0.push((name.to_string(), last + 1 - first));
    }
}

impl<'ast> Visit<'ast> for Functions {
    fn visit_item(&mut self, item: &'ast Item) {
        if !test_only(item_attrs(item)) {
            visit::visit_item(self, item);
        }
    }
    fn visit_impl_item(&mut self, item: &'ast ImplItem) {
        if !test_only(impl_item_attrs(item)) {
            visit::visit_impl_item(self, item);
        }
    }
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        self.add(&f.sig.ident, &f.sig, &f.block);
        visit::visit_item_fn(self, f);
    }
    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        self.add(&f.sig.ident, &f.sig, &f.block);
        visit::visit_impl_item_fn(self, f);
    }
}

/// Every function of every crate's `src` outside `#[cfg(test)]` code, by its span in the parsed
/// file (nested functions and methods counted on their own too).
#[test]
fn no_function_is_over_150_lines() {
    let mut long = Vec::new();
    let mut counted = 0;
    for m in &members() {
        for (path, text) in source_files(m) {
            let file = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let mut found = Functions::default();
            found.visit_file(&file);
            counted += found.0.len();
            long.extend(
                found
                    .0
                    .into_iter()
                    .filter(|(_, n)| *n > MAX_FUNCTION_LINES)
                    .map(|(name, n)| {
                        format!("{}/src/{}: {name} ({n} lines)", m.dir, path.display())
                    }),
            );
        }
    }
    assert!(counted > 1000, "only {counted} functions read");
    assert!(
        long.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines: {long:?}"
    );
}

/// The span reader counts a function from `fn` to its closing brace, and skips test modules.
#[test]
fn a_function_is_measured_from_fn_to_its_brace() {
    let text = "/// doc\nfn a() {\n    let x = 1;\n}\n#[cfg(test)]\nmod t {\n    fn b() {}\n}\nimpl S {\n    fn c(&self) { }\n}\n";
    let mut found = Functions::default();
    found.visit_file(&syn::parse_file(text).unwrap());
    assert_eq!(found.0, vec![("a".to_string(), 3), ("c".to_string(), 1)]);
}

#[test]
fn no_module_is_moved_by_a_path_attribute() {
    let mut moved = Vec::new();
    for m in &members() {
        for (module, names) in member_names(m) {
            moved.extend(
                names
                    .moved_mods
                    .iter()
                    .map(|x| format!("{} {}: mod {x}", m.dir, show(&module))),
            );
        }
    }
    assert!(moved.is_empty(), "#[path] modules: {moved:?}");
}

#[test]
fn crates_depend_only_on_the_crates_below_them() {
    let members = members();
    let unlisted: Vec<&str> = members
        .iter()
        .map(|m| m.package.as_str())
        .filter(|p| !LAYERS.iter().any(|(l, _)| l == p))
        .collect();
    assert!(
        unlisted.is_empty(),
        "workspace crates without a layer in LAYERS: {unlisted:?}"
    );
    let found: Vec<String> = breaches(&members).iter().map(|b| b.to_string()).collect();
    assert!(
        found.is_empty(),
        "dependencies across the layers:\n{}",
        found.join("\n")
    );
}

/// The renderer reads the shading model's tables (`shading`), never the tracer that builds them:
/// neither its manifest (dependencies and dev-dependencies) nor its code names `mc`.
#[test]
fn gpu_does_not_depend_on_mc() {
    let left: Vec<String> = breaches(&members())
        .iter()
        .filter(|b| b.krate == "gpu" && b.dep == "mc")
        .map(|b| b.to_string())
        .collect();
    assert!(left.is_empty(), "gpu still uses mc:\n{}", left.join("\n"));
    let manifest: toml::Table = std::fs::read_to_string(root().join("crates/gpu/Cargo.toml"))
        .unwrap()
        .parse()
        .unwrap();
    for table in ["dependencies", "dev-dependencies", "build-dependencies"] {
        let deps = manifest.get(table).and_then(|t| t.as_table());
        assert!(
            deps.is_none_or(|d| !d.contains_key("mc")),
            "crates/gpu/Cargo.toml [{table}] names mc"
        );
    }
}

/// Every `tests/*.rs` file is a `[[test]]` of some workspace package (Cargo finds no test file
/// outside a package's own folder), and every registered file exists.
#[test]
fn every_test_file_is_registered() {
    let root = root();
    let registered: BTreeSet<PathBuf> = members()
        .iter()
        .flat_map(|m| m.tests.iter().map(|t| lexical(&root.join(&m.dir).join(t))))
        .collect();
    let files: BTreeSet<PathBuf> = std::fs::read_dir(root.join("tests"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .collect();
    assert!(
        files.iter().any(|f| f.ends_with("cli_simulate.rs")),
        "{files:?}"
    );
    let missing: Vec<_> = files.difference(&registered).collect();
    let stale: Vec<_> = registered.iter().filter(|p| !p.is_file()).collect();
    assert!(
        missing.is_empty() && stale.is_empty(),
        "tests/ files no package registers: {missing:?}; registered but absent: {stale:?}"
    );
}

/// The README's test command is the one `.ci/run` runs.
#[test]
fn the_readme_test_command_is_what_ci_runs() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let ci = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    let command = ci
        .lines()
        .rev()
        .find(|l| l.starts_with("cargo test "))
        .expect(".ci/run runs cargo test");
    assert!(
        readme.contains(&format!("\n{command}\n")),
        "README.md does not show `{command}`"
    );
}

// ---------------------------------------------------------------------------------------------
// The reader's own regression tests: in-memory crates, (file under src/, text)

/// The module graph of an in-memory crate.
fn graph_of(files: &[(&str, &str)]) -> Graph {
    let files: Vec<(PathBuf, String)> = files
        .iter()
        .map(|(f, t)| (PathBuf::from(f), t.to_string()))
        .collect();
    module_graph(&parse_crate(&files))
}

/// The modules `module` (`a::b`, the root `crate`) names in `g`, as printed.
fn edges(g: &Graph, module: &str) -> Vec<String> {
    let (_, to) = g
        .iter()
        .find(|(m, _)| show(m) == module)
        .expect("a module of the graph");
    to.keys().map(|m| show(m)).collect()
}

/// The circles of `g`, each its modules as printed, joined by `, `.
fn circle_names(g: &Graph) -> Vec<String> {
    let names = |c: &BTreeSet<Module>| c.iter().map(|m| show(m)).collect::<Vec<_>>().join(", ");
    circles(g).iter().map(names).collect()
}

/// Modules `a`, `a::b`, `a::c`, `d` and `x` beside the root: `x.rs` is the file under test.
fn with_x(x: &str) -> Graph {
    graph_of(&[
        ("lib.rs", "mod a; mod d; mod x; pub fn parse_count() {}"),
        ("a/mod.rs", "pub mod b; pub mod c; pub struct X;"),
        ("a/b.rs", "pub fn f() {}"),
        ("a/c.rs", "pub fn f() {}"),
        ("d.rs", "pub fn f() {}"),
        ("x.rs", x),
    ])
}

/// What broke: the old reader stopped at `{` and never saw the modules of a brace group; a root
/// item in the group (`parse_count`) is the root, an ancestor, and no edge.
#[test]
fn a_brace_group_names_each_module_in_it() {
    assert_eq!(
        edges(&with_x("use crate::{parse_count, a, d};"), "x"),
        ["a", "d"]
    );
}

#[test]
fn nested_brace_groups_name_each_leaf() {
    let g = with_x("use crate::{a::{b, c::f}, d::{self}};");
    assert_eq!(edges(&g, "x"), ["a::b", "a::c", "d"]);
}

/// `self` in a group names the module itself; an item of a module names that module.
#[test]
fn self_in_a_group_names_the_module() {
    assert_eq!(edges(&with_x("use crate::a::{self, X};"), "x"), ["a"]);
}

/// `super` of `a/b.rs` and of `a/mod.rs` alike is the module above the file's own; `super::super`
/// two above. A module's ancestors are no edges.
#[test]
fn super_and_super_super_climb_from_the_files_module() {
    let g = graph_of(&[
        ("lib.rs", "mod a; mod d;"),
        ("a/mod.rs", "mod b; mod c; use super::d::f;"),
        (
            "a/b.rs",
            "use super::c::f; use super::super::d; use super::X;",
        ),
        ("a/c.rs", "fn g() { super::super::d::f() }"),
        ("d.rs", "pub fn f() {}"),
    ]);
    assert_eq!(edges(&g, "a"), ["d"]);
    assert_eq!(edges(&g, "a::b"), ["a::c", "d"]);
    assert_eq!(edges(&g, "a::c"), ["d"]);
}

#[test]
fn a_pub_use_reexport_names_its_module() {
    assert_eq!(
        edges(
            &with_x("pub use crate::a::b::f as g;\npub use crate::d::*;"),
            "x"
        ),
        ["a::b", "d"]
    );
}

/// Paths in code count, not only `use`: calls, types, and macro arguments.
#[test]
fn a_path_in_code_names_its_module() {
    assert_eq!(
        edges(&with_x("fn f() { crate::a::b::f(); }"), "x"),
        ["a::b"]
    );
    assert_eq!(edges(&with_x("fn f(_: &crate::a::X) {}"), "x"), ["a"]);
    assert_eq!(
        edges(
            &with_x("fn f() -> String { format!(\"{:?}\", crate::d::f()) }"),
            "x"
        ),
        ["d"]
    );
    assert_eq!(
        edges(
            &with_x("macro_rules! m { () => { $crate::a::c::f() } }"),
            "x"
        ),
        ["a::c"]
    );
}

/// A renamed import names its module, and its new name is no crate (`mc` below is `crate::d`).
#[test]
fn a_renamed_import_names_its_module() {
    let g = with_x("use crate::a::X as Y;\nuse crate::d as mc;\nfn f() { mc::f() }");
    assert_eq!(edges(&g, "x"), ["a", "d"]);
    let names = names_in("use crate::d as mc;\nfn f() { mc::f() }").unwrap();
    let modules = BTreeSet::from([vec![], vec!["d".to_string()], vec!["x".to_string()]]);
    let in_x = |n: &Named| resolve(n, &["x".to_string()], &modules, &names.local_names);
    assert!(
        names
            .paths
            .iter()
            .all(|n| in_x(n) != Some(Target::Outside("mc".into())))
    );
}

/// Test modules are not the crate: neither inline nor in their own file.
#[test]
fn a_test_module_is_ignored() {
    let g = with_x("fn f() {}\n#[cfg(test)]\nmod tests {\n    use crate::d;\n}\n");
    assert!(edges(&g, "x").is_empty());
    let g = with_x(
        "#[cfg(all(test, unix))]\nuse crate::d::f;\n\
         struct S;\nimpl S {\n    #[cfg(test)]\n    fn t() { crate::a::b::f() }\n}\n",
    );
    assert!(edges(&g, "x").is_empty());
    let g = graph_of(&[
        ("lib.rs", "mod a; mod b;"),
        ("a/mod.rs", "#[cfg(test)]\nmod tests;\npub fn f() {}"),
        ("a/tests.rs", "use crate::b::g;"),
        ("b.rs", "pub fn g() { crate::a::f() }"),
    ]);
    assert!(circle_names(&g).is_empty());
}

/// What broke: `simulate` calls `crate::table::merge` while `table` imports
/// `use crate::{parse_count, progress, simulate}`, a circle the text-scanning test never saw.
#[test]
fn the_simulate_table_circle_is_found() {
    let g = graph_of(&[
        (
            "main.rs",
            "mod progress; mod simulate; mod table;\nfn parse_count() {}",
        ),
        ("progress.rs", "pub fn bar() {}"),
        (
            "simulate.rs",
            "use crate::{parse_count, progress};\n\
             pub fn merge(texts: &[String]) -> anyhow::Result<()> {\n\
                 if texts.iter().any(|t| crate::table::is_table_shard(t)) {\n\
                     return crate::table::merge(texts);\n\
                 }\n\
                 Ok(())\n\
             }\n",
        ),
        (
            "table.rs",
            "use crate::{parse_count, progress, simulate};\n\
             pub fn is_table_shard(_: &str) -> bool { false }\n\
             pub fn merge(_: &[String]) -> anyhow::Result<()> { simulate::merge(&[]) }\n",
        ),
    ]);
    assert_eq!(circle_names(&g), ["simulate, table"]);
    let circle = &circles(&g)[0];
    assert_eq!(
        describe(circle, &g),
        "simulate, table: simulate -> table (crate::table::is_table_shard) \
         -> simulate (crate::simulate)"
    );
}

/// A longer circle through `crate::`, `super::` and a nested module, beside a child that uses its
/// parent (allowed), and gone once one step is test-only.
#[test]
fn a_circle_through_a_nested_module_is_found() {
    let files = |c: &'static str| {
        graph_of(&[
            ("lib.rs", "mod a;\nmod b;\nmod c;\n"),
            ("a.rs", "use crate::b::inner::Z;\n"),
            ("b/mod.rs", "pub struct X;\npub mod inner;\n"),
            (
                "b/inner.rs",
                "pub struct Z;\nuse super::X; // a child using its parent\nuse crate::c::Y;\n",
            ),
            ("c.rs", c),
        ])
    };
    let g = files("pub struct Y;\nuse super::a; // crate::b would be in a comment\n");
    assert_eq!(circle_names(&g), ["a, b::inner, c"]);
    assert!(circle_names(&files("pub struct Y;\n#[cfg(test)]\nuse super::a;\n")).is_empty());
}

/// A parent that names its child by a relative path (`mod b; use b::X;`) has that edge, and it
/// closes a circle like any other.
#[test]
fn a_relative_path_into_a_child_module_names_it() {
    let g = graph_of(&[
        ("lib.rs", "mod a; mod c;"),
        ("a/mod.rs", "mod b;\nuse b::X;\n"),
        ("a/b.rs", "pub struct X;\nuse crate::c::Y;\n"),
        (
            "c.rs",
            "pub struct Y;\nfn f() { self::g(); crate::a::h() }\nfn g() {}",
        ),
    ]);
    assert_eq!(circle_names(&g), ["a, a::b, c"]);
}

/// Another crate is seen by its name in code (`mc::…`), with a leading `::` too, but not where a
/// child module or an import has that name.
#[test]
fn a_crate_named_in_code_is_used() {
    let libs = BTreeMap::from([("mc", "mc"), ("fit", "fit")]);
    let crate_of = |files: &[(&str, &str)]| {
        let files: Vec<_> = files
            .iter()
            .map(|(f, t)| (PathBuf::from(f), t.to_string()))
            .collect();
        let used = crates_used(&parse_crate(&files), &libs);
        used.into_iter()
            .map(|(m, dep, _)| format!("{}: {dep}", show(&m)))
            .collect::<Vec<_>>()
    };
    let gpu = [
        ("lib.rs", "mod shift;\nmod fit;\npub fn f() { fit::g() }"),
        (
            "shift.rs",
            "pub fn from_mc(spec: &mc::BatchSpec) { ::mc::incidence::run(spec) }",
        ),
        ("fit.rs", "pub fn g() {}"),
    ];
    assert_eq!(crate_of(&gpu), ["shift: mc"]);
    assert!(
        crate_of(&[
            ("lib.rs", "mod t;\nuse crate::t as mc;\nfn f() { mc::g() }"),
            ("t.rs", "")
        ])
        .is_empty()
    );
}

/// `[dependencies]` and its build and target-specific forms count, by package; dev-dependencies
/// do not.
#[test]
fn manifest_dependencies_are_read_by_package() {
    let manifest: toml::Table = r#"
        [package]
        name = "gpu"
        [dependencies]
        fit.workspace = true
        tables = { path = "../shading", package = "shading" }
        [target.'cfg(unix)'.dependencies]
        mc = { workspace = true }
        [build-dependencies]
        report.workspace = true
        [dev-dependencies]
        tempfile = "3"
    "#
    .parse()
    .unwrap();
    let deps: Vec<String> = dependency_packages(&manifest).into_iter().collect();
    assert_eq!(deps, ["fit", "mc", "report", "shading"]);
}

/// A crate the table names but the workspace lacks is skipped; an unlisted one has no layer.
#[test]
fn layers_say_who_may_depend_on_whom() {
    assert_eq!(may_depend("gpu", "mc"), Some(false));
    assert_eq!(may_depend("gpu", "shading"), Some(true));
    assert_eq!(may_depend("sss-benches", "report"), Some(true));
    assert_eq!(may_depend("mc", "fit"), Some(false));
    assert_eq!(may_depend("not-a-crate", "mc"), None);
}
