//! `sss view`: the browser page (`web/`) with a material's package and its scenes' frames,
//! written into a folder to serve (`render::Site`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use crate::cache::{ProfileSource, TableFlags};
use crate::files::Outputs;
use crate::library;

#[derive(Args)]
pub struct ViewArgs {
    /// Material (built-in name or material .toml path) [default: the references' (--reference
    /// DIR), else skin1]
    pub material: Option<String>,

    /// Scenes the page offers (repeatable; the first is its default): sphere, fin or an .obj path
    /// (named after its file) [default: sphere and fin]
    #[arg(long = "scene", value_name = "SCENE")]
    pub scenes: Vec<String>,

    /// A path-traced reference beside a scene (repeatable): a folder that
    /// `scripts/references/images.py --arrays` wrote (OUT/SCENE: its view.json and arrays.npz; the
    /// page gets that scene in the reference's camera, light and material), or NAME=FILE.png (an
    /// image shown as it is beside the page's scene NAME)
    #[arg(long = "reference", value_name = "DIR|NAME=FILE.png")]
    pub references: Vec<String>,

    /// Image width [px] (the frames are drawn at this size, as `sss render --width`)
    #[arg(long, default_value_t = 960)]
    pub width: u32,

    /// Image height [px]
    #[arg(long, default_value_t = 540)]
    pub height: u32,

    #[command(flatten)]
    pub tables: TableFlags,

    /// The page's folder [default: out/view]
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Where the profile and tables come from
    #[command(flatten)]
    pub source: ProfileSource,
}

pub fn run(a: ViewArgs) -> Result<()> {
    let runs = (a.references.iter().filter(|r| !r.contains('=')))
        .map(|d| render::Reference::read(std::path::Path::new(d)))
        .collect::<Result<Vec<_>, _>>()?;
    let given = a.material.as_deref().map(library::material).transpose()?;
    let (named, mut scenes) = render::Reference::page(given, &a.scenes, runs)?;
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| crate::common::default_out().join("view"));
    for (name, file) in a.references.iter().filter_map(|r| r.split_once('=')) {
        let png = std::fs::read(file).with_context(|| format!("cannot read --reference {file}"))?;
        render::SiteScene::set_reference(&mut scenes, name, png)
            .with_context(|| format!("--reference {name}={file}"))?;
    }
    let mut request = a.source.request(named, &a.tables)?;
    request.frame.width = a.width;
    request.frame.height = a.height;
    let mut files = Outputs::default();
    let site = (a.source).build(&mut files, |p, bars| {
        render::Site::build(&request, &scenes, p, bars)
    })?;
    files.add_in(&out, site.files().to_vec());
    files.commit()?;
    let names: Vec<&str> = scenes.iter().map(|s| s.name.as_str()).collect();
    eprintln!(
        "wrote the page for {} ({}) to {}\n\
         serve it and open it in a browser with WebGPU (Chrome or Edge 113+, Safari 26, Firefox 141+):\n  \
         python3 -m http.server --directory {} 8000   then   http://localhost:8000/?scene={}\n\
         or without a server: chromium --allow-file-access-from-files {}/index.html",
        site.package.slug,
        names.join(", "),
        out.display(),
        out.display(),
        names[0],
        out.display()
    );
    Ok(())
}
