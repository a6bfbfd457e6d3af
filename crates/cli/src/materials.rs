//! `sss materials`: the built-in library as a table (or JSON).

use anyhow::Result;
use clap::Args;
use mc::builtin;
use serde_json::json;

use crate::library;

#[derive(Args)]
pub struct MaterialsArgs {
    /// Print the table as JSON on stdout
    #[arg(long)]
    json: bool,
}

pub fn list(args: MaterialsArgs) -> Result<()> {
    let all = library::all()?;
    if args.json {
        let v: Vec<_> = all
            .iter()
            .map(|n| builtin::json(&n.slug, &n.material))
            .collect();
        return crate::common::print_json(&json!({ "materials": v }));
    }
    let rows: Vec<(&str, &mc::Material)> =
        all.iter().map(|n| (n.slug.as_str(), &n.material)).collect();
    builtin::table_lines(&rows)
        .iter()
        .for_each(|l| println!("{l}"));
    println!(
        "\nMFP = 1/(σa + σs(1−g)), the transport mean free path (thesis Table 6.1). Files: materials/*.toml."
    );
    Ok(())
}
