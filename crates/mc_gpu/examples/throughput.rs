//! Interactions per second of the GPU tracer against the CPU tracer on the same material and
//! photons, the medians of three runs interleaved (GPU, CPU, GPU, CPU, …) so that both see the
//! same machine. A measurement, not a test.
//!
//! ```text
//! cargo run --profile ci -p mc_gpu --example throughput -- [MATERIAL|FILE.mci] [PHOTONS] [RUNS]
//! ```
//! Defaults: skin1, 10⁶ photons per channel, 3 runs. An `.mci` file's runs are traced as layered
//! samples (profile-only: Rd(r, α), Tt(r, α) and absorption per layer, what the GPU tallies), so
//! that published GPU tracers' benchmark geometries (`examples/inputs/`: GPU-MCML's seven-layer
//! skin, MCX's cube60 medium) can be set beside ours per interaction; the mean interactions per
//! photon are printed for that. The GPU is the adapter wgpu finds first (a discrete GPU, else
//! lavapipe on the same cores as the CPU tracer's rayon threads).

use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map_or("skin1", String::as_str);
    let photons: u64 = args.get(1).map_or(Ok(1_000_000), |s| s.parse())?;
    let runs: usize = args.get(2).map_or(Ok(3), |s| s.parse())?;
    let gpu = gpu::Gpu::new()?;
    let tracer = mc_gpu::Tracer::new(&gpu)?;
    // One traced sample: the GPU's outputs and the CPU's, timed.
    type Trace<'a> = Box<dyn Fn() -> Result<Vec<mc::Output>, Box<dyn std::error::Error>> + 'a>;
    let (gpu_trace, cpu_trace, what): (Trace, Trace, String) = if name.ends_with(".mci") {
        let text = std::fs::read_to_string(name)?;
        let mut specs: Vec<mc::RunSpec> = mc::mci::parse(&text, name, 1)?
            .into_iter()
            .map(|r| r.spec)
            .collect();
        // Published photons/ms of MCML-like tracers count MCML's walk, A(r, z) tallied and so
        // without mc's importance roulette: its interactions per photon, to normalise them.
        for s in &specs {
            let o = mc::run(
                &mc::RunSpec {
                    photons,
                    ..s.clone()
                },
                &|_| {},
            )?;
            let per = o.interactions as f64 / o.photons as f64;
            println!(
                "{name}: {per:.1} interactions per photon as MCML traces it (A(r, z) tallied)"
            );
        }
        for s in &mut specs {
            s.photons = photons;
            s.tallies.absorption_rz = false;
            s.tallies.absorption_rz_se = false;
        }
        let cpu_specs = specs.clone();
        let what = format!("{name}: {} run(s) of {photons} photons", specs.len());
        let (gpu, tracer) = (&gpu, &tracer);
        (
            Box::new(move || {
                Ok(specs
                    .iter()
                    .map(|s| tracer.run(gpu, s, &|_| {}))
                    .collect::<Result<_, _>>()?)
            }),
            Box::new(move || {
                Ok(cpu_specs
                    .iter()
                    .map(|s| mc::run(s, &|_| {}))
                    .collect::<Result<_, _>>()?)
            }),
            what,
        )
    } else {
        let material = mc::Material::builtin(name)?;
        let spec = mc::SimConfig::thesis()?.batch(&[&material], photons, 1, true)?;
        let what = format!(
            "{name}, {photons} photons per channel, {} channel(s)",
            spec.channels.len()
        );
        let cpu_spec = spec.clone();
        let (gpu, tracer) = (&gpu, &tracer);
        (
            Box::new(move || Ok(tracer.run_batch(gpu, &spec, &|_| {})?)),
            Box::new(move || Ok(mc::run_batch(&cpu_spec, &|_| {})?)),
            what,
        )
    };
    println!(
        "{what}; GPU: {}; CPU: {} rayon threads",
        gpu.adapter_name,
        rayon::current_num_threads()
    );
    let (mut gpu_rates, mut cpu_rates) = (Vec::new(), Vec::new());
    for run in 1..=runs {
        let start = Instant::now();
        let g = gpu_trace()?;
        let g_s = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let c = cpu_trace()?;
        let c_s = start.elapsed().as_secs_f64();
        let events = |o: &[mc::Output]| o.iter().map(|o| o.interactions).sum::<u64>() as f64;
        let photons = |o: &[mc::Output]| o.iter().map(|o| o.photons).sum::<u64>() as f64;
        gpu_rates.push(events(&g) / g_s);
        cpu_rates.push(events(&c) / c_s);
        println!(
            "run {run}: GPU {g_s:.2} s, {:.2e} interactions/s, {:.1} per photon; \
             CPU {c_s:.2} s, {:.2e} interactions/s, {:.1} per photon",
            gpu_rates[run - 1],
            events(&g) / photons(&g),
            cpu_rates[run - 1],
            events(&c) / photons(&c)
        );
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (g, c) = (median(&mut gpu_rates), median(&mut cpu_rates));
    println!(
        "median: GPU {g:.3e} interactions/s, CPU {c:.3e} interactions/s, GPU/CPU {:.3}",
        g / c
    );
    Ok(())
}
