use mc::*;
fn main() {
    let a = 0.1; let mu_t = 10.0;
    let layer = Layer { n: 1.0, mu_a: mu_t * (1.0 - a), mu_s: mu_t * a, g: 0.0, thickness: 1.0e8 };
    let spec = RunSpec { sample: Sample::single(layer), grid: Grid { dr: 0.01, dz: 0.01, nr: 100, nz: 40, na: 30 }, photons: 100000, seed: 1, tallies: TallySet::default() };
    let o = run(&spec, &|_| {}).unwrap();
    println!("rd {:?} a {:?} tt {:?} photons {} inter {}", o.rd, o.a, o.tt, o.photons, o.interactions);
}
