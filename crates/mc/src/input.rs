//! Reading a text input a user names (a material, config, `.mci`, `.mco`, profile, kernel or
//! shard file) whole, through a size cap, so that a wrong path (`/dev/zero`, a disk image) fails
//! instead of filling memory or reading forever. Used by the CLI and the Python module.

/// The largest input file read [bytes]: 256 MiB, far above any profile, kernel, material, MCI
/// or shard file.
pub const INPUT_CAP: u64 = 256 << 20;

/// Reads a text input whole, refusing one longer than [`INPUT_CAP`] (read through a cap, so a
/// device or pipe that never ends is refused too). Errors read like [`std::fs::read_to_string`]'s.
pub fn read_text(path: impl AsRef<std::path::Path>) -> std::io::Result<String> {
    use std::io::Read;
    let mut text = String::new();
    std::fs::File::open(path)?
        .take(INPUT_CAP + 1)
        .read_to_string(&mut text)?;
    if text.len() as u64 > INPUT_CAP {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "longer than {} MiB, the cap on inputs: is it the right file?",
                INPUT_CAP >> 20
            ),
        ));
    }
    Ok(text)
}

/// Each file's text with its name, for messages; `what` names the kind of file in errors
/// (`cannot read shard out/shard-1-of-2.json: …`).
pub fn read_named(
    paths: &[std::path::PathBuf],
    what: &str,
) -> crate::Result<Vec<(String, String)>> {
    paths
        .iter()
        .map(|p| {
            let name = p.display().to_string();
            let text = read_text(p)
                .map_err(|e| crate::McError::file(format!("cannot read {what} {name}"), e))?;
            Ok((name, text))
        })
        .collect()
}
