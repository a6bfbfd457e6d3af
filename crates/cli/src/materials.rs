//! `sss materials`: the built-in library as a table (or JSON).

use anyhow::Result;
use clap::Args;
use mc::CHANNELS;
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
            .map(|n| {
                let m = &n.material;
                json!({
                    "material": n.slug, "name": m.name, "source": m.source, "eta": m.eta,
                    "channels": CHANNELS.iter().enumerate().map(|(c, ch)| (ch.to_string(), json!({
                        "sigma_a_per_cm": m.sigma_a[c], "sigma_s_per_cm": m.sigma_s[c], "g": m.g[c],
                        "albedo": m.albedo(c), "mfp_cm": m.mfp(c),
                    }))).collect::<serde_json::Map<_, _>>(),
                })
            })
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({ "materials": v }))?
        );
        return Ok(());
    }
    println!(
        "{:<11} {:>2} {:>10} {:>10} {:>6} {:>5} {:>9} {:>10}",
        "material", "ch", "σa [1/cm]", "σs [1/cm]", "g", "η", "albedo", "MFP [cm]"
    );
    for n in &all {
        let m = &n.material;
        for (c, ch) in CHANNELS.iter().enumerate() {
            let name = if c == 0 { n.slug.as_str() } else { "" };
            println!(
                "{:<11} {:>2} {:>10.4} {:>10.4} {:>6.3} {:>5.2} {:>9.6} {:>10.5}",
                name,
                ch,
                m.sigma_a[c],
                m.sigma_s[c],
                m.g[c],
                m.eta,
                m.albedo(c),
                m.mfp(c)
            );
        }
    }
    println!(
        "\nMFP = 1/(σa + σs(1−g)), the transport mean free path (thesis Table 6.1). Files: materials/*.toml."
    );
    Ok(())
}
