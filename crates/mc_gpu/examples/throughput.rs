//! Interactions per second of the GPU tracer against the CPU tracer on the same material and
//! photons, the medians of three runs interleaved (GPU, CPU, GPU, CPU, …) so that both see the
//! same machine. A measurement, not a test.
//!
//! ```text
//! cargo run --profile ci -p mc_gpu --example throughput -- [MATERIAL] [PHOTONS] [RUNS]
//! ```
//! Defaults: skin1, 10⁶ photons per channel, 3 runs. The GPU is the adapter wgpu finds first (a
//! discrete GPU, else lavapipe on the same cores as the CPU tracer's rayon threads).

use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map_or("skin1", String::as_str);
    let photons: u64 = args.get(1).map_or(Ok(1_000_000), |s| s.parse())?;
    let runs: usize = args.get(2).map_or(Ok(3), |s| s.parse())?;
    let gpu = gpu::Gpu::new()?;
    let material = mc::Material::builtin(name)?;
    let spec = mc::SimConfig::thesis()?.batch(&[&material], photons, 1, true)?;
    let tracer = mc_gpu::Tracer::new(&gpu)?;
    println!(
        "{name}, {photons} photons per channel, {} channel(s); GPU: {}; CPU: {} rayon threads",
        spec.channels.len(),
        gpu.adapter_name,
        rayon::current_num_threads()
    );
    let (mut gpu_rates, mut cpu_rates) = (Vec::new(), Vec::new());
    for run in 1..=runs {
        let start = Instant::now();
        let g = tracer.run_batch(&gpu, &spec, &|_| {})?;
        let g_s = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let c = mc::run_batch(&spec, &|_| {})?;
        let c_s = start.elapsed().as_secs_f64();
        let events = |o: &[mc::Output]| o.iter().map(|o| o.interactions).sum::<u64>() as f64;
        gpu_rates.push(events(&g) / g_s);
        cpu_rates.push(events(&c) / c_s);
        println!(
            "run {run}: GPU {g_s:.2} s, {:.2e} interactions/s; \
             CPU {c_s:.2} s, {:.2e} interactions/s",
            gpu_rates[run - 1],
            cpu_rates[run - 1]
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
