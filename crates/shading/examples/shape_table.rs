//! Skin1's shape table (issue 47, step 2): the energy ratio, shift and width per curvature and
//! thickness at 0° and 45°, per channel with standard errors, the time it took to build, and
//! what share of a half-space's diffuse reflectance the table's window holds (Skin1's channels
//! and two media of low albedo), and how far the lookup's linear interpolation lies from bodies
//! run halfway between the nodes.
//!
//! `cargo run --profile ci -p shading --example shape_table [PHOTONS]` (default
//! `shading::SHAPE_PHOTONS` per run).

use mc::body::{Body, Coefficients, run_body};
use shading::shape::{curved_body, half_space, shape_run};
use shading::{
    SHAPE_CURVATURES, SHAPE_PHOTONS, SHAPE_THICKNESSES, SHAPE_WINDOW, ShapeEntry, ShapeTable,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let photons = match std::env::args().nth(1) {
        Some(p) => p.parse::<f64>()? as u64,
        None => SHAPE_PHOTONS,
    };
    let material = mc::Material::builtin("skin1")?;
    let config = mc::SimConfig::thesis()?;
    let spec = config.batch(&[&material], photons, config.seed, true)?;
    let start = std::time::Instant::now();
    let table = ShapeTable::from_mc(&spec, &|_| {})?;
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "Skin1, {photons} photons per run, {} threads: built in {seconds:.1} s",
        rayon::current_num_threads()
    );
    println!(
        "σ_tr = {:.3} {:.3} {:.3} cm⁻¹ (R G B); window {SHAPE_WINDOW}/σ_tr",
        table.sigma_tr[0], table.sigma_tr[1], table.sigma_tr[2]
    );

    let cell = |e: &ShapeEntry| {
        format!(
            "{:.3}±{:.3} {:>6.3}±{:.3} {:.3}±{:.3}",
            e.energy.value,
            e.energy.se,
            10.0 * e.shift_cm.value,
            10.0 * e.shift_cm.se,
            10.0 * e.width_cm.value,
            10.0 * e.width_cm.se
        )
    };
    for theta in [0, 4] {
        println!();
        println!("θ = {}°: E, shift [mm], width [mm] per channel", 10 * theta);
        println!("{:>10}  {:<36} {:<36} {:<36}", "", "R", "G", "B");
        let rows = SHAPE_CURVATURES
            .iter()
            .map(|k| format!("κ {k:>6}"))
            .zip(&table.curvature)
            .chain(
                SHAPE_THICKNESSES
                    .iter()
                    .map(|t| format!("τ {t:>6}"))
                    .zip(&table.thickness),
            );
        for (name, row) in rows {
            let e = &row[theta];
            println!(
                "{name:>10}  {:<36} {:<36} {:<36}",
                cell(&e[0]),
                cell(&e[1]),
                cell(&e[2])
            );
        }
    }

    let media = shading::shape::channel_media(&spec);

    println!();
    println!(
        "halfway between nodes at 0° (κ: the mean of two, τ: the geometric mean), E run with \
         {photons} photons against the lookup's; R G B"
    );
    let halfway = SHAPE_CURVATURES
        .windows(2)
        .map(|w| {
            let k = 0.5 * (w[0] + w[1]);
            (format!("κ {k:>7}"), k, None)
        })
        .chain(SHAPE_THICKNESSES.windows(2).map(|w| {
            let t = (w[0] * w[1]).sqrt();
            (format!("τ {t:>7.3}"), 0.0, Some(t))
        }));
    // Runs with a seed apart from the table's, so that the two disagree by their noise.
    let window = |body: Body, c: usize| {
        run_body(&shape_run(body, media[c], 0.0, photons, 2), &|_| {}).map(|o| o.reflected.window)
    };
    let halves = [0, 1, 2].map(|c| window(half_space(table.sigma_tr[c]), c));
    for (name, kappa, tau) in halfway {
        let cells = [0, 1, 2].map(|c| {
            let s = table.sigma_tr[c];
            let (body, lookup) = match tau {
                None => (
                    curved_body(kappa as f64, s),
                    table.at(kappa * s as f32, 1.0).energy[c],
                ),
                Some(t) => (
                    Body::Slab {
                        thickness_cm: t as f64 / s,
                    },
                    table.slab_at(t / s as f32, 1.0).energy[c],
                ),
            };
            match (window(body, c), &halves[c]) {
                (Ok(b), Ok(h)) => {
                    let e = ShapeEntry::relative(&b, h).energy;
                    format!(
                        "{:.3}±{:.3} vs {lookup:.3} ({:+.1} se)",
                        e.value,
                        e.se,
                        (lookup as f64 - e.value) / e.se
                    )
                }
                (Err(e), _) => e.to_string(),
                (_, Err(e)) => e.to_string(),
            }
        });
        println!(
            "{name:>10}  {:<30} {:<30} {:<30}",
            cells[0], cells[1], cells[2]
        );
    }

    println!();
    println!(
        "the half-space's diffuse reflectance within the window, of its total (2·10⁵ photons)"
    );
    let skin1 = [0, 1, 2].map(|c| (["Skin1 R", "Skin1 G", "Skin1 B"][c], media[c]));
    let low = [
        (
            "albedo 0.5, g 0",
            Coefficients {
                n: 1.3,
                mu_a: 5.0,
                mu_s: 5.0,
                g: 0.0,
            },
        ),
        (
            "albedo 0.2, g 0.9",
            Coefficients {
                n: 1.3,
                mu_a: 8.0,
                mu_s: 2.0,
                g: 0.9,
            },
        ),
    ];
    for (name, c) in skin1.into_iter().chain(low) {
        for theta in [0.0, 45.0, 80.0] {
            let s = shape_run(half_space(c.sigma_tr()), c, theta, 200_000, 1);
            let o = run_body(&s, &|_| {})?;
            let w = o.reflected.window.r;
            println!(
                "  {name:<18} {theta:>4}°: {:.5} (R_W {:.4} ± {:.4} of R {:.4})",
                w.value / o.r.value,
                w.value,
                w.se,
                o.r.value
            );
        }
    }
    Ok(())
}
