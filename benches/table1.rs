//! Per-stage benches at the canvas sizes of the paper's Table 1.
//!
//! Inputs are drawn in [`common`] (no files, no Python). At start one row per case goes to
//! stderr: mesh size and one-shot milliseconds per stage (fresh stage structs, after one
//! warm-up pass), beside the paper's figures (Table 1: vertices, DOF, mesh deformation; Table 2:
//! VSM). Then criterion times each stage:
//!
//! * `vsm`: `VsmBuilder::build`, the builder (and its scratch) reused as in a stream;
//! * `mesh`: `Mesh::build`;
//! * `solve`: `Solver::solve` with a fresh solver (symbolic and numeric factorization, repair);
//! * `solve_warm`: the same with the solver reused on the same mesh (symbolic factorization kept,
//!   as for a stream whose mesh is unchanged);
//! * `render`: `Renderer::render` into a reused output image;
//! * `frame`: [`vizretarget::retarget`], all stages (plus one copy of the input).

mod common;

use common::Case;
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use std::time::{Duration, Instant};
use vizretarget::{
    retarget, Image, Mesh, MeshOptions, Options, Renderer, SolveStats, Solver, VsmBuilder, Warp,
};

/// One pass through the stages with fresh structs; milliseconds per stage.
struct OneShot {
    mesh: Mesh,
    warp: Warp,
    stats: SolveStats,
    vsm_ms: f64,
    mesh_ms: f64,
    solve_ms: f64,
    render_ms: f64,
    frame_ms: f64,
}

fn one_shot(case: &Case) -> OneShot {
    let ms = |t: Instant| t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    let vsm = VsmBuilder::new().build(case.image.as_ref());
    let vsm_ms = ms(t);
    let t = Instant::now();
    let mesh = Mesh::build(&vsm, &MeshOptions::default());
    let mesh_ms = ms(t);
    let t = Instant::now();
    let (warp, stats) = Solver::default()
        .solve(&mesh, &vsm, case.target)
        .expect("solve");
    let solve_ms = ms(t);
    let t = Instant::now();
    let mut out = Image::new(case.target);
    Renderer::new().render(case.image.as_ref(), &mesh, &warp, &mut out);
    let render_ms = ms(t);
    let t = Instant::now();
    let frame = retarget(&case.image, case.target, &Options::default()).expect("retarget");
    let frame_ms = ms(t);
    assert_eq!(frame.image.size(), case.target);
    assert_eq!(warp.folded_triangles(&mesh), 0);
    OneShot {
        mesh,
        warp,
        stats,
        vsm_ms,
        mesh_ms,
        solve_ms,
        render_ms,
        frame_ms,
    }
}

fn print_table(cases: &[Case]) {
    eprintln!();
    eprintln!(
        "Table 1 canvases, one-shot ms (fresh stage structs, after one warm-up pass); (paper)"
    );
    eprintln!(
        "{:<30} {:>20} {:>11} {:>6} {:>11} {:>8} {:>13} {:>6} {:>12} {:>7} {:>7} {:>10}",
        "case (paper's)",
        "size -> target",
        "V (paper)",
        "T",
        "DOF (paper)",
        "unknowns",
        "VSM (paper)",
        "mesh",
        "solve (paper)",
        "render",
        "frame",
        "folds/rep"
    );
    for case in cases {
        one_shot(case); // warm-up: page faults, allocator, code cache
        let r = one_shot(case);
        let p = case.paper;
        eprintln!(
            "{:<30} {:>20} {:>11} {:>6} {:>11} {:>8} {:>13} {:>6.1} {:>13} {:>7.1} {:>7.1} {:>10}",
            format!("{} ({})", case.name, p.label),
            format!("{} -> {}", case.image.size(), case.target),
            format!("{} ({})", r.mesh.vertices().len(), p.vertices),
            r.mesh.triangles().len(),
            format!("{} ({})", r.mesh.dof(), p.dof),
            r.stats.unknowns,
            format!("{:.1} ({:.0})", r.vsm_ms, p.vsm_ms),
            r.mesh_ms,
            format!("{:.1} ({:.0})", r.solve_ms, p.deform_ms),
            r.render_ms,
            r.frame_ms,
            format!("{}/{}", r.stats.folds_first_solve, r.stats.repair_rounds),
        );
        debug_assert_eq!(r.warp.target(), case.target);
    }
    eprintln!(
        "paper rows: SGM, GC, China map, IG (Table 1: V, DOF, mesh deformation; Table 2: VSM)"
    );
    eprintln!();
}

fn table1(c: &mut Criterion) {
    let cases = common::cases();
    print_table(&cases);
    for case in &cases {
        let src = case.image.as_ref();
        let vsm = VsmBuilder::new().build(src);
        let mesh = Mesh::build(&vsm, &MeshOptions::default());
        let (warp, _) = Solver::default()
            .solve(&mesh, &vsm, case.target)
            .expect("solve");

        let mut group = c.benchmark_group(case.name);
        group.bench_function("vsm", |b| {
            let mut builder = VsmBuilder::new();
            b.iter(|| builder.build(black_box(src)))
        });
        group.bench_function("mesh", |b| {
            b.iter(|| Mesh::build(black_box(&vsm), &MeshOptions::default()))
        });
        group.bench_function("solve", |b| {
            b.iter(|| Solver::default().solve(black_box(&mesh), &vsm, case.target))
        });
        group.bench_function("solve_warm", |b| {
            let mut solver = Solver::default();
            b.iter(|| solver.solve(black_box(&mesh), &vsm, case.target))
        });
        group.bench_function("render", |b| {
            let mut renderer = Renderer::new();
            let mut out = Image::new(case.target);
            b.iter(|| renderer.render(black_box(src), &mesh, &warp, &mut out))
        });
        group.bench_function("frame", |b| {
            let options = Options::default();
            b.iter(|| retarget(black_box(&case.image), case.target, &options))
        });
        group.finish();
    }
}

fn config() -> Criterion {
    Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
}

criterion_group! {
    name = benches;
    config = config();
    targets = table1
}
criterion_main!(benches);
