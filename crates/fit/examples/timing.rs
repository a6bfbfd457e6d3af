fn main() {
    let path = std::env::args().nth(1).unwrap();
    let p = fit::Profile::from_csv(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    let k = fit::ground_truth(&p, 0, None);
    println!("side {}", k.side());
    let t = std::time::Instant::now();
    let (_, e) = fit::svd(&k, 6);
    println!("svd6 {:?} its {} {:?}", t.elapsed(), e.iterations, e.stop);
    let t = std::time::Instant::now();
    let g = fit::Guided::default().fit(&k);
    println!("guided {:?} its {} {:?} cerr {:e}", t.elapsed(), g.iterations, g.stop, g.constraint_error);
    let t = std::time::Instant::now();
    let d = fit::Gaussians::fit_up_to(&k, 6);
    println!("deon {:?} {:?}", t.elapsed(), d[5]);
    let t = std::time::Instant::now();
    let ev = fit::metrics::ImageEval::new(&k, 256, 128);
    println!("eval prep {:?} factor {}", t.elapsed(), ev.factor);
    let t = std::time::Instant::now();
    let r = ev.rms(&g.kernel);
    println!("eval model {:?} {:?}", t.elapsed(), r);
}
