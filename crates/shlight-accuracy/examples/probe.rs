fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let t = std::time::Instant::now();
    let r = shlight_accuracy::suite::run(shlight_accuracy::suite::SuiteOptions { quick }, &|s| {
        eprintln!("{:?} {s}", t.elapsed())
    });
    for row in &r.rows {
        println!(
            "{:14} {:20} {:>10} {:>3} {:10.3e} {:10.3e} {:>10} {:>8} {:?} {}",
            row.case,
            row.method,
            row.setting(),
            row.lmax,
            row.mean_rel_err,
            row.max_rel_err,
            row.bound.map(|b| format!("{b:.2e}")).unwrap_or("-".into()),
            row.slope.map(|s| format!("{s:.3}")).unwrap_or("-".into()),
            row.max_z.map(|z| format!("{z:.2}")),
            row.pass
        );
    }
    eprintln!("{:?}", t.elapsed());
}
