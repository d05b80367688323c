//! Issue 20: a seeded mutation fuzz over the shipped scene files. Every mutant goes through
//! `SceneFile::parse` (parse and validate); those that parse and stay small are built
//! (`SceneFile::check`, what `staggered-fluid check` runs) and some of those stepped. Nothing
//! may panic (an abort or a hang fails the test run by itself); every rejection is a
//! `FluidError::Scene` located at a line of the file; a built scene steps to Ok or to an error,
//! never to a NaN.
use staggered_fluid::scenes::{SceneFile, ShapeSpec};
use staggered_fluid::FluidError;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// xorshift64*: a fixed seed, so a failure reproduces.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Byte ranges of the numbers in `text`.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts =
            b[i].is_ascii_digit() || (b[i] == b'-' && i + 1 < b.len() && b[i + 1].is_ascii_digit());
        let inside_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if starts && !inside_word {
            let s = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_digit() || b"+-.eE".contains(&b[i])) {
                i += 1;
            }
            out.push((s, i));
        } else {
            i += 1;
        }
    }
    out
}

const EXTREMES: &[&str] = &[
    "0",
    "-1",
    "1e30",
    "-1e30",
    "1e-30",
    "4294967295",
    "18446744073709551615",
    "1e9",
    "1e-9",
    "NaN",
    "inf",
    "-0.0",
    "3",
    "1e6",
    "0.5",
];

fn mutate(text: &str, rng: &mut Rng) -> String {
    let lines: Vec<&str> = text.lines().collect();
    match rng.below(8) {
        // a number replaced by an extreme or scaled (most mutants: numbers carry the sizes)
        0..=3 => {
            let nums = numbers(text);
            let (s, e) = nums[rng.below(nums.len())];
            let old: f64 = text[s..e].parse().unwrap_or(1.0);
            let new = if rng.below(2) == 0 {
                EXTREMES[rng.below(EXTREMES.len())].to_string()
            } else {
                let f = [-1.0, 0.0, 0.3, 3.0, 10.0, 1e3][rng.below(6)];
                format!("{}", old * f)
            };
            format!("{}{}{}", &text[..s], new, &text[e..])
        }
        4 => {
            let k = rng.below(lines.len());
            let mut l = lines.clone();
            l.remove(k);
            l.join("\n")
        }
        5 => {
            let k = rng.below(lines.len());
            let mut l = lines.clone();
            l.insert(k, lines[k]);
            l.join("\n")
        }
        6 => {
            let mut b = text.as_bytes().to_vec();
            let k = rng.below(b.len());
            let set = b"()[],:-.0123456789eE \"abxyz_";
            b[k] = set[rng.below(set.len())];
            String::from_utf8_lossy(&b).into_owned()
        }
        _ => {
            let mut b = text.as_bytes().to_vec();
            b.remove(rng.below(b.len()));
            String::from_utf8_lossy(&b).into_owned()
        }
    }
}

/// Rough number of carriers a scene asks for (fluid blocks, tanks, walls, bodies' shells),
/// so that the fuzz builds only scenes of a size a test can afford.
fn size(s: &SceneFile) -> f64 {
    let dx = s.params.spacing as f64;
    let vol =
        |a: [f32; 3], b: [f32; 3]| (0..3).map(|k| (b[k] - a[k]).abs() as f64).product::<f64>();
    let area = |a: [f32; 3], b: [f32; 3]| {
        let e: Vec<f64> = (0..3)
            .map(|k| (b[k] - a[k]).abs() as f64 + 6.0 * dx)
            .collect();
        2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0])
    };
    let mut n = 0.0;
    for b in &s.fluid {
        n += vol(b.min, b.max) / dx.powi(3);
    }
    for t in &s.tanks {
        n += 5.0 * area(t.min, t.max) / dx.powi(2);
    }
    for w in &s.walls {
        n += 5.0 * area(w.min, w.max) / dx.powi(2);
    }
    for d in &s.deformables {
        // a melting body's whole lattice, any other's points and shell
        n += 2.0 * (2.0 * shape_reach(&d.shape) as f64 / dx).powi(3);
    }
    for c in &s.cloths {
        n += (c.size[0] as f64 / dx + 1.0) * (c.size[1] as f64 / dx + 1.0);
    }
    for b in &s.bodies {
        for c in &b.colliders {
            let r = shape_reach(&c.shape) as f64;
            n += 5.0 * 24.0 * r * r / dx.powi(2);
        }
    }
    n
}

/// The largest extent of a shape from its origin, m.
fn shape_reach(shape: &ShapeSpec) -> f32 {
    match shape {
        ShapeSpec::Ball { radius } => *radius,
        ShapeSpec::Cuboid { half_extents } => half_extents.iter().fold(0.0, |a, &b| b.max(a)),
        ShapeSpec::Cylinder {
            half_height,
            radius,
        }
        | ShapeSpec::Capsule {
            half_height,
            radius,
        } => half_height.max(*radius) + radius,
        ShapeSpec::Ellipsoid { semi_axes, .. } => semi_axes.iter().fold(0.0, |a, &b| b.max(a)),
        ShapeSpec::ConvexHull { points } => points
            .iter()
            .flatten()
            .fold(0.0, |a: f32, b| b.abs().max(a)),
        ShapeSpec::TriMesh { vertices, .. } => vertices
            .iter()
            .flatten()
            .fold(0.0, |a: f32, b| b.abs().max(a)),
        ShapeSpec::Compound { parts } => parts.iter().fold(0.0, |a: f32, p| {
            let o = p.offset.iter().fold(0.0, |a: f32, b| b.abs().max(a));
            a.max(o + shape_reach(&p.shape))
        }),
    }
}

fn located(e: &FluidError) -> bool {
    matches!(e, FluidError::Scene { line, .. } if *line > 0)
}

#[test]
fn scene_mutants_never_panic_and_every_rejection_is_located() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    files.sort();
    let texts: Vec<String> = files
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    // `FUZZ_SEED` and `FUZZ_MUTANTS` run a fresh, larger fuzz by hand (CI: the fixed seed)
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<u64>().ok());
    let mut rng = Rng(env("FUZZ_SEED").unwrap_or(0x5eed_2026_1202) | 1);
    let mutants = env("FUZZ_MUTANTS").unwrap_or(3000);
    let (max_built, max_stepped) = (mutants / 10, mutants / 50);
    let (mut parsed, mut built, mut stepped, mut rejected, mut limits) = (0, 0, 0, 0, 0);
    let mut slowest = (0.0f64, String::new());
    let t0 = std::time::Instant::now();
    for k in 0..mutants {
        let t = std::time::Instant::now();
        let f = rng.below(texts.len());
        let mut m = mutate(&texts[f], &mut rng);
        // a second mutation now and then, so that mutants also differ in two places
        if rng.below(4) == 0 {
            m = mutate(&m, &mut rng);
        }
        let name = format!("mutant{k}.ron");
        let what = format!("mutant {k} of {}:\n{m}", files[f].display());
        let spec = catch_unwind(AssertUnwindSafe(|| SceneFile::parse(&m, &name)))
            .unwrap_or_else(|_| panic!("parse panicked on {what}"));
        let spec = match spec {
            Ok(s) => s,
            Err(e) => {
                assert!(located(&e), "unlocated rejection {e} of {what}");
                limits += e.to_string().contains("exceeds") as usize;
                rejected += 1;
                continue;
            }
        };
        parsed += 1;
        if size(&spec) > 60_000.0 || built >= max_built {
            continue;
        }
        let scene = catch_unwind(AssertUnwindSafe(|| SceneFile::check(&m, &name)))
            .unwrap_or_else(|_| panic!("check panicked on {what}"));
        built += 1;
        let mut scene = match scene {
            Ok(s) => s,
            Err(e) => {
                assert!(located(&e), "unlocated rejection {e} of {what}");
                rejected += 1;
                continue;
            }
        };
        // steps of the mutant's own dt, if it is a game's (a 4 s step is 600 legitimate
        // substeps of work, which a test cannot afford hundreds of)
        if stepped >= max_stepped || scene.dt > 0.05 {
            continue;
        }
        stepped += 1;
        // two steps of the scene's own dt (its substeps bounded by the cap, refused beyond)
        let dt = scene.dt as f64;
        let run = catch_unwind(AssertUnwindSafe(|| scene.run(2.0 * dt, |_, _| {})))
            .unwrap_or_else(|_| panic!("stepping panicked on {what}"));
        if run.is_ok() {
            let fl = scene.world.fluid();
            assert!(
                fl.x.iter().chain(&fl.v).all(|v| v.is_finite()),
                "non-finite state after an Ok run of {what}"
            );
        }
        let took = t.elapsed().as_secs_f64();
        if took > slowest.0 {
            let changed = m
                .lines()
                .zip(texts[f].lines())
                .find(|(a, b)| a != b)
                .map(|(a, _)| a.trim().to_string())
                .unwrap_or_default();
            slowest = (took, format!("{} `{changed}`", files[f].display()));
        }
    }
    println!(
        "{mutants} mutants: {parsed} parsed, {built} built, {stepped} stepped, {rejected} \
         rejected (all located, {limits} by a size limit), {:.1} s; slowest mutant {:.2} s \
         ({})",
        t0.elapsed().as_secs_f64(),
        slowest.0,
        slowest.1
    );
    assert!(
        parsed > 300 && built > 100 && stepped > 20,
        "the fuzz must reach the builder"
    );
}
