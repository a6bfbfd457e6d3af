//! The command reference against the binary: `docs/commands.md` names every command `sss --help`
//! lists and every option of each command's own `--help` (moved here from the house test, which
//! no longer builds `sss`).

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

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
