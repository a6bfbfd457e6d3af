//! How a body's shape changes what a material returns (issue 47's first measurement): total
//! diffuse reflectance of a sphere, a spherical cavity and a slab against the half-space's (a slab
//! of 1000 diffusion lengths), at sizes of 0.5–1000 diffusion lengths 1/σ_tr, entered at 0° and
//! 45°, with the shift of the exits along the plane of incidence.
//!
//! `cargo run --profile ci -p mc --example bodies [PHOTONS]` (default 2·10⁵ per run).

use mc::body::{Body, BodySpec, Coefficients, SurfaceGrid, run_body};
use mc::{Estimate, Incidence};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let photons = match std::env::args().nth(1) {
        Some(p) => p.parse::<f64>()? as u64,
        None => 200_000,
    };
    // A skin-like medium behind a skin-like boundary [cm⁻¹].
    let coefficients = Coefficients {
        n: 1.4,
        mu_a: 1.0,
        mu_s: 30.0,
        g: 0.8,
    };
    let l = 1.0 / coefficients.sigma_tr();
    let grid = SurfaceGrid {
        dr: 0.02 * l,
        nr: 500,
        n_azimuth: 4,
        n_exit: 9,
    };
    let run = |body: Body, theta_deg: f64| {
        let spec = BodySpec {
            body,
            coefficients,
            incidence: Incidence { theta_deg },
            grid,
            photons,
            seed: 1,
        };
        run_body(&spec, &|_| {})
    };
    let ratio = |a: Estimate, b: Estimate| a.value / b.value;
    println!(
        "medium: n 1.4, μa 1, μs 30 cm⁻¹, g 0.8; 1/σ_tr = {l:.4} cm; {photons} photons per run"
    );
    println!("R / R(half-space) and the shift along the plane of incidence [cm]");
    println!(
        "{:>7} {:>5}  {:>8} {:>8} {:>8} {:>8}  {:>8} {:>8}",
        "σ_tr·L", "θ", "sphere", "cavity", "slab", "slab T", "shift s", "shift c"
    );
    for theta in [0.0, 45.0] {
        let half = run(
            Body::Slab {
                thickness_cm: 1000.0 * l,
            },
            theta,
        )?;
        for size in [0.5, 1.0, 2.0, 5.0, 10.0, 1000.0] {
            let s = run(
                Body::Sphere {
                    radius_cm: size * l,
                },
                theta,
            )?;
            let c = run(
                Body::Cavity {
                    radius_cm: size * l,
                },
                theta,
            )?;
            let t = run(
                Body::Slab {
                    thickness_cm: size * l,
                },
                theta,
            )?;
            println!(
                "{size:>7} {theta:>5}  {:>8.3} {:>8.3} {:>8.3} {:>8.4}  {:>8.4} {:>8.4}",
                ratio(s.r, half.r),
                ratio(c.r, half.r),
                ratio(t.r, half.r),
                t.t.value,
                s.reflected.shift.value,
                c.reflected.shift.value
            );
        }
        println!(
            "half-space at {theta}°: R = {:.4} ± {:.4}, shift {:.4} cm",
            half.r.value, half.r.se, half.reflected.shift.value
        );
    }
    Ok(())
}
