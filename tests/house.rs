//! The house's own rules, checked on every test run: no module of any crate imports itself around
//! a loop (issue 31: each module can be read and changed alone), and every test file under
//! `tests/` is registered, so none is silently left out of `cargo test`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// A module's path inside its crate: `["analytic", "burley"]`; the crate root is `[]`.
type Module = Vec<String>;

/// Every `.rs` file under `src`, by module path (`mod.rs`, `lib.rs` and `main.rs` name their
/// folder's module).
fn modules(src: &Path) -> BTreeMap<Module, PathBuf> {
    fn walk(dir: &Path, src: &Path, out: &mut BTreeMap<Module, PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                walk(&p, src, out);
            } else if p.extension().is_some_and(|e| e == "rs") {
                let rel = p.strip_prefix(src).unwrap().with_extension("");
                let mut m: Module = rel
                    .iter()
                    .map(|s| s.to_string_lossy().into_owned())
                    .collect();
                if ["mod", "lib", "main"].contains(&m.last().unwrap().as_str()) {
                    m.pop();
                }
                out.insert(m, p);
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(src, src, &mut out);
    out
}

/// The code of a file without line comments and without its test module (everything from the
/// first `#[cfg(test)]` on, as the house writes tests last).
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap();
    text.lines()
        .map(|l| l.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The `a::b::c` after each `keyword::` in `code` (`crate` or `super`), as segments.
fn paths_after(code: &str, keyword: &str) -> Vec<Vec<String>> {
    let pat = format!("{keyword}::");
    let mut out = Vec::new();
    for (i, _) in code.match_indices(&pat) {
        let before = code[..i].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &code[i + pat.len()..];
        let mut segs = Vec::new();
        let mut tail = rest;
        loop {
            let n = tail
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(tail.len());
            if n == 0 {
                break;
            }
            segs.push(tail[..n].to_string());
            match tail[n..].strip_prefix("::") {
                Some(t) => tail = t,
                None => break,
            }
        }
        out.push(segs);
    }
    out
}

/// Module → the other modules of its crate it names (not its own ancestors: a child may use its
/// parent's items).
fn imports(files: &BTreeMap<Module, PathBuf>) -> BTreeMap<Module, BTreeSet<Module>> {
    let resolve = |parts: Vec<String>| -> Option<Module> {
        (1..=parts.len())
            .rev()
            .map(|k| parts[..k].to_vec())
            .find(|m| files.contains_key(m))
    };
    let mut g = BTreeMap::new();
    for (m, p) in files {
        let text = code(&std::fs::read_to_string(p).unwrap());
        let mut to = BTreeSet::new();
        // `super` of `b/inner.rs` and of `b/mod.rs` alike is the module above the file's own.
        let parent: Module = m[..m.len().saturating_sub(1)].to_vec();
        let named = paths_after(&text, "crate").into_iter().chain(
            paths_after(&text, "super")
                .into_iter()
                .map(|s| parent.iter().cloned().chain(s).collect()),
        );
        for t in named.filter_map(resolve) {
            if t != *m && !m.starts_with(&t) {
                to.insert(t);
            }
        }
        g.insert(m.clone(), to);
    }
    g
}

/// The strongly connected components of more than one module (Tarjan).
fn circles(g: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<Module>> {
    struct State<'a> {
        g: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'a Module, usize>,
        low: BTreeMap<&'a Module, usize>,
        stack: Vec<&'a Module>,
        out: Vec<Vec<Module>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a Module) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        for w in &s.g[v] {
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
            let mut c = Vec::new();
            while let Some(w) = s.stack.pop() {
                c.push(w.clone());
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
        stack: Vec::new(),
        out: Vec::new(),
    };
    for v in g.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

fn crate_circles(src: &Path) -> Vec<String> {
    circles(&imports(&modules(src)))
        .into_iter()
        .map(|c| {
            let mut names: Vec<String> = c.iter().map(|m| m.join("::")).collect();
            names.sort();
            names.join(", ")
        })
        .collect()
}

#[test]
fn no_crate_has_a_module_cycle() {
    let mut found = Vec::new();
    let mut crates = 0;
    for entry in std::fs::read_dir(format!("{ROOT}/crates")).unwrap() {
        let src = entry.unwrap().path().join("src");
        if src.is_dir() {
            crates += 1;
            for c in crate_circles(&src) {
                found.push(format!("{}: {c}", src.display()));
            }
        }
    }
    assert!(crates >= 5, "found {crates} crates under crates/");
    assert!(
        found.is_empty(),
        "module import circles:\n{}",
        found.join("\n")
    );
}

/// The checker finds a circle when there is one: a → b::inner → c → a, through `crate::`,
/// `super::` and a nested module, beside a child that uses its parent (allowed).
#[test]
fn the_cycle_check_sees_a_circle() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path();
    std::fs::create_dir(src.join("b")).unwrap();
    for (file, text) in [
        ("lib.rs", "mod a;\nmod b;\nmod c;\n"),
        ("a.rs", "use crate::b::inner::Z;\n"),
        ("b/mod.rs", "pub struct X;\npub mod inner;\n"),
        (
            "b/inner.rs",
            "pub struct Z;\nuse super::X; // a child using its parent\nuse crate::c::Y;\n",
        ),
        (
            "c.rs",
            "pub struct Y;\nuse super::a; // crate::b would be in a comment\n",
        ),
    ] {
        std::fs::write(src.join(file), text).unwrap();
    }
    assert_eq!(crate_circles(src), ["a, b::inner, c"]);
    // Cut the loop: c no longer names a.
    std::fs::write(
        src.join("c.rs"),
        "pub struct Y;\n#[cfg(test)]\nuse super::a;\n",
    )
    .unwrap();
    assert!(crate_circles(src).is_empty());
}

/// Every `tests/*.rs` file is a `[[test]]` of the CLI's package (Cargo does not find test files
/// outside a package's own folder), and every registered file exists.
#[test]
fn every_test_file_is_registered() {
    let manifest = std::fs::read_to_string(format!("{ROOT}/crates/cli/Cargo.toml")).unwrap();
    let registered: BTreeSet<String> = manifest
        .lines()
        .filter_map(|l| l.trim().strip_prefix("path = \"../../tests/"))
        .filter_map(|l| l.strip_suffix('"'))
        .map(str::to_string)
        .collect();
    let files: BTreeSet<String> = std::fs::read_dir(format!("{ROOT}/tests"))
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            name.ends_with(".rs").then_some(name)
        })
        .collect();
    assert!(files.contains("house.rs"), "{files:?}");
    let missing: Vec<_> = files.difference(&registered).collect();
    let stale: Vec<_> = registered.difference(&files).collect();
    assert!(
        missing.is_empty() && stale.is_empty(),
        "tests/ files not in crates/cli/Cargo.toml: {missing:?}; registered but absent: {stale:?}"
    );
}

/// The README's test command is the one `.ci/run` runs.
#[test]
fn the_readme_test_command_is_what_ci_runs() {
    let readme = std::fs::read_to_string(format!("{ROOT}/README.md")).unwrap();
    let ci = std::fs::read_to_string(format!("{ROOT}/.ci/run")).unwrap();
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

/// Every command `sss --help` lists has its row in `docs/commands.md`, and every option of its
/// own `--help` is named there, so the reference cannot silently drop a command or a flag.
#[test]
fn every_command_and_option_is_documented() {
    let help = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_sss"))
            .args(args)
            .output()
            .unwrap();
        String::from_utf8(out.stdout).unwrap()
    };
    let docs = std::fs::read_to_string(format!("{ROOT}/docs/commands.md")).unwrap();
    let top = help(&["--help"]);
    let commands: Vec<&str> = top
        .split("Commands:")
        .nth(1)
        .expect("a Commands: section")
        .lines()
        .skip(1) // the rest of the "Commands:" line
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.len() >= 10, "{commands:?}");
    let missing: Vec<_> = commands
        .iter()
        .filter(|c| !docs.contains(&format!("`sss {c}")))
        .collect();
    assert!(missing.is_empty(), "not in docs/commands.md: {missing:?}");
    let mut undocumented = Vec::new();
    for c in &commands {
        // An option line starts with `-x, --flag` or `--flag`; `--help` and `--version` are clap's.
        for line in help(&[c, "--help"]).lines() {
            let t = line.trim_start();
            let t = t.strip_prefix('-').map_or(t, |r| match r.split_once(", ") {
                Some((short, rest)) if short.len() == 1 => rest,
                _ => t,
            });
            let Some(flag) = t.strip_prefix("--") else {
                continue;
            };
            let name: String = flag
                .chars()
                .take_while(|ch| ch.is_ascii_alphanumeric() || *ch == '-')
                .collect();
            if !["help", "version"].contains(&name.as_str()) && !docs.contains(&format!("--{name}"))
            {
                undocumented.push(format!("sss {c} --{name}"));
            }
        }
    }
    assert!(
        undocumented.is_empty(),
        "options not named in docs/commands.md: {undocumented:?}"
    );
}
