//! He 2012 Table 3-style timing of the dam break at several resolutions, plus SSOR-PCG against
//! Jacobi-PCG. `cargo run --release --example table3 [steps] [spacing mm ...]`
//! (`RAYON_NUM_THREADS=1` for one thread; `PARAMS` overrides parameters, e.g. the solver).
//!
//! The column (a = 0.1 m, height 2a) is 12 particles thick (`LAYERS=n` for n; `LAYERS=40` at
//! 2.5 mm makes a 3-D column a deep, 128k carriers); spacing 5, 2.5, 1.25, 0.625 and
//! 0.5 mm give about 10k, 40k, 150k, 600k and 1M fluid carriers (default: the first three).
//! Timings are the mean over `steps` steps after 5 warm-up steps; peak memory is the process
//! high-water mark (VmHWM) after each size (sizes run smallest first, so it is the current
//! size's), and KiB/fluid divides it by the fluid carriers (solid carriers included in it).
use staggered_fluid::{scenes, FluidParams, Preconditioner};

fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM")).map(|l| {
                l.split_whitespace()
                    .nth(1)
                    .unwrap_or("0")
                    .parse::<f64>()
                    .unwrap_or(0.0)
            })
        })
        .unwrap_or(0.0)
        / 1024.0
}

fn main() {
    let steps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let mut sizes: Vec<f32> = std::env::args()
        .skip(2)
        .filter_map(|s| s.parse::<f32>().ok())
        .map(|mm| mm / 1000.0)
        .collect();
    if sizes.is_empty() {
        sizes = vec![0.005, 0.0025, 0.00125];
    }
    let params = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let layers: usize = std::env::var("LAYERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(12);
    println!(
        "threads: {}, solver {:?}",
        rayon::current_num_threads(),
        params.solver
    );
    println!("| fluid | solid | pairs | fluid pairs | neighbours s | p^d s | surface s | creating s | assembly s | solve s | other s | step s | us/particle-step | PCG it | E | peak MiB | KiB/fluid |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &dx in &sizes {
        let mut sc = scenes::dam_break(0.1, dx, layers, params.clone()).unwrap();
        for _ in 0..5 {
            sc.world.step(sc.gravity, sc.dt).unwrap();
        }
        let mut t = staggered_fluid::StageTimes::default();
        let (mut it, mut e, mut pairs) = (0u64, 0.0f64, 0usize);
        for _ in 0..steps {
            let r = sc.world.step(sc.gravity, sc.dt).unwrap();
            t.add(&r.stages);
            it += r.pcg_iterations as u64;
            e += r.error;
            pairs = r.n_pairs;
        }
        let n = steps as f64;
        let nf = sc.world.fluid().len();
        println!(
            "| {} | {} | {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.2} | {:.1} | {:.1e} | {:.0} | {:.2} |",
            nf,
            sc.world.solid_carriers().len(),
            pairs,
            {
                let l = sc.world.neighbor_lists();
                (0..nf).map(|i| l.fluid_range(i).len()).sum::<usize>()
            },
            t.neighbors / n,
            t.density / n,
            t.surface / n,
            t.staggered / n,
            t.assembly / n,
            t.solve / n,
            t.other / n,
            t.total() / n,
            1e6 * t.total() / n / nf as f64,
            it as f64 / n,
            e / n,
            peak_rss_mib(),
            peak_rss_mib() * 1024.0 / nf as f64
        );
    }
    if std::env::var("SKIP_PRECONDITIONERS").is_ok() {
        return;
    }
    println!();
    println!("| preconditioner | PCG it/step | solve s/step | E |");
    println!("|---|---|---|---|");
    for pre in [
        Preconditioner::BlockSsor,
        Preconditioner::Jacobi,
        Preconditioner::None,
    ] {
        let p = FluidParams {
            preconditioner: pre,
            relative_residual: 1e-3,
            ..Default::default()
        };
        let mut sc = scenes::dam_break(0.1, 0.0025, 12, p).unwrap();
        let (mut it, mut s, mut e) = (0u64, 0.0, 0.0);
        for _ in 0..steps {
            let r = sc.world.step(sc.gravity, sc.dt).unwrap();
            it += r.pcg_iterations as u64;
            s += r.stages.solve;
            e += r.error;
        }
        let n = steps as f64;
        println!(
            "| {pre:?} | {:.1} | {:.4} | {:.1e} |",
            it as f64 / n,
            s / n,
            e / n
        );
    }
}
