//! The paper's Tables 1 and 2 at its nine canvas sizes and targets, beside its published
//! figures: `cargo bench --bench paper_tables` (a plain `main`, no criterion).
//!
//! Inputs are drawn here, deterministically (a fixed xorshift seed per case), one kind of
//! visualization per row of the paper: scatter on a map (SGM), a graph on a map (GGM), graph
//! communities (GC), an infographic (IG), hexagon-binned points, node-link graphs, a social
//! network, a heat map and a map of many regions with points (China Map). Labels are set in
//! the crate's bundled font so that text is text.
//!
//! What is timed, per case, as the median of [`REPEATS`] runs after one warm-up run:
//! * **Table 1, mesh deformation** = building the mesh (key-point sampling and Delaunay for the
//!   mesh; the lattice for the grid) + the solve (energy assembly, symbolic and numeric sparse
//!   Cholesky, fold-over repair rounds), each with fresh structs, on the VSM computed before.
//!   Not included: the VSM (Table 2) and rendering. The grid is the uniform-grid baseline
//!   (`Mesh::lattice` with cells of α = 20 px, the same budget `w·h/α²` the mesh samples
//!   from) on the same energy and solver.
//! * **Table 2** = `VsmBuilder::build` with a fresh builder (frames above 0.6 MP get a map at
//!   half resolution, see `saliency::FULL_RESOLUTION_MAX_PX`).
//!
//! DOF is the number of free vertex coordinates (2 per interior vertex, 1 per side vertex, 0
//! per corner). The paper does not define how it counts DOF; its grid figures are about 5.5
//! per vertex, so they are not comparable one to one, but the ratio mesh/grid is.

use ab_glyph::{point, Font, FontRef, PxScale, ScaleFont};
use std::time::Instant;
use vizretarget::{Image, Mesh, MeshOptions, Size, Solver, VsmBuilder};

/// Timed runs per measurement (after one warm-up run); the median is reported.
const REPEATS: usize = 7;
/// Grid cell of the baseline, in px (the default α).
const GRID_CELL_PX: f64 = 20.0;

/// One row of the paper's Tables 1 and 2.
struct Paper {
    name: &'static str,
    size: (u32, u32),
    target: (u32, u32),
    grid_v: usize,
    grid_dof: usize,
    grid_ms: f64,
    mesh_v: usize,
    mesh_dof: usize,
    mesh_ms: f64,
    /// Table 2: clutter map and VSM.
    clutter_ms: f64,
    vsm_ms: f64,
}

#[derive(Clone, Copy)]
enum Kind {
    ScatterMap,
    GraphMap,
    Communities,
    Infographic,
    HexPoints,
    Graphs,
    SocialNetwork,
    HeatMap,
    RegionMap,
}

const PAPER: [(Paper, Kind); 9] = [
    (
        Paper {
            name: "SGM",
            size: (876, 374),
            target: (385, 374),
            grid_v: 741,
            grid_dof: 4104,
            grid_ms: 175.0,
            mesh_v: 324,
            mesh_dof: 586,
            mesh_ms: 19.0,
            clutter_ms: 3441.0,
            vsm_ms: 472.0,
        },
        Kind::ScatterMap,
    ),
    (
        Paper {
            name: "GGM",
            size: (876, 414),
            target: (438, 414),
            grid_v: 1012,
            grid_dof: 5670,
            grid_ms: 263.0,
            mesh_v: 589,
            mesh_dof: 3242,
            mesh_ms: 64.0,
            clutter_ms: 3813.0,
            vsm_ms: 525.0,
        },
        Kind::GraphMap,
    ),
    (
        Paper {
            name: "GC",
            size: (1500, 800),
            target: (750, 800),
            grid_v: 2886,
            grid_dof: 16644,
            grid_ms: 4739.0,
            mesh_v: 853,
            mesh_dof: 4824,
            mesh_ms: 161.0,
            clutter_ms: 12177.0,
            vsm_ms: 1749.0,
        },
        Kind::Communities,
    ),
    (
        Paper {
            name: "IG",
            size: (678, 680),
            target: (1066, 680),
            grid_v: 1849,
            grid_dof: 10584,
            grid_ms: 1337.0,
            mesh_v: 611,
            mesh_dof: 3498,
            mesh_ms: 58.0,
            clutter_ms: 4631.0,
            vsm_ms: 653.0,
        },
        Kind::Infographic,
    ),
    (
        Paper {
            name: "Hex Points",
            size: (750, 495),
            target: (375, 495),
            grid_v: 950,
            grid_dof: 3800,
            grid_ms: 206.0,
            mesh_v: 408,
            mesh_dof: 2310,
            mesh_ms: 19.0,
            clutter_ms: 3762.0,
            vsm_ms: 534.0,
        },
        Kind::HexPoints,
    ),
    (
        Paper {
            name: "Graphs",
            size: (600, 363),
            target: (300, 363),
            grid_v: 465,
            grid_dof: 2520,
            grid_ms: 42.0,
            mesh_v: 405,
            mesh_dof: 2322,
            mesh_ms: 19.0,
            clutter_ms: 2370.0,
            vsm_ms: 303.0,
        },
        Kind::Graphs,
    ),
    (
        Paper {
            name: "Social Network",
            size: (600, 299),
            target: (300, 299),
            grid_v: 589,
            grid_dof: 2356,
            grid_ms: 54.0,
            mesh_v: 280,
            mesh_dof: 1560,
            mesh_ms: 12.0,
            clutter_ms: 1973.0,
            vsm_ms: 254.0,
        },
        Kind::SocialNetwork,
    ),
    (
        Paper {
            name: "Heat-map",
            size: (1126, 563),
            target: (663, 563),
            grid_v: 1653,
            grid_dof: 6612,
            grid_ms: 1024.0,
            mesh_v: 479,
            mesh_dof: 2694,
            mesh_ms: 30.0,
            clutter_ms: 6477.0,
            vsm_ms: 943.0,
        },
        Kind::HeatMap,
    ),
    (
        Paper {
            name: "China Map",
            size: (1320, 791),
            target: (660, 791),
            grid_v: 2688,
            grid_dof: 10752,
            grid_ms: 3932.0,
            mesh_v: 393,
            mesh_dof: 2142,
            mesh_ms: 32.0,
            clutter_ms: 10456.0,
            vsm_ms: 1553.0,
        },
        Kind::RegionMap,
    ),
];

/// Measured figures of one case.
struct Row {
    vsm_ms: f64,
    mesh_v: usize,
    mesh_dof: usize,
    mesh_build_ms: f64,
    mesh_solve_ms: f64,
    mesh_ms: f64,
    mesh_folds: usize,
    grid_v: usize,
    grid_dof: usize,
    grid_ms: f64,
    grid_folds: usize,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

fn measure(image: &Image, target: Size) -> Row {
    let vsm = VsmBuilder::new().build(image.as_ref());
    let (mut vsm_t, mut build_t, mut solve_t, mut mesh_t, mut grid_t) =
        (vec![], vec![], vec![], vec![], vec![]);
    let (mut mesh_v, mut mesh_dof, mut grid_v, mut grid_dof) = (0, 0, 0, 0);
    let (mut mesh_folds, mut grid_folds) = (0, 0);
    for run in 0..=REPEATS {
        let t = Instant::now();
        let v = VsmBuilder::new().build(image.as_ref());
        let vsm_ms = ms_since(t);
        std::hint::black_box(v);

        let t = Instant::now();
        let mesh = Mesh::build(&vsm, &MeshOptions::default());
        let build_ms = ms_since(t);
        let t = Instant::now();
        let (warp, _) = Solver::default()
            .solve(&mesh, &vsm, target)
            .expect("mesh solve");
        let solve_ms = ms_since(t);

        let t = Instant::now();
        let grid = Mesh::lattice(image.size(), GRID_CELL_PX);
        let (gwarp, _) = Solver::default()
            .solve(&grid, &vsm, target)
            .expect("grid solve");
        let grid_ms = ms_since(t);

        (mesh_v, mesh_dof) = (mesh.vertices().len(), mesh.dof());
        (grid_v, grid_dof) = (grid.vertices().len(), grid.dof());
        mesh_folds = warp.folded_triangles(&mesh);
        grid_folds = gwarp.folded_triangles(&grid);
        if run == 0 {
            continue; // warm-up: page faults, allocator, caches
        }
        vsm_t.push(vsm_ms);
        build_t.push(build_ms);
        solve_t.push(solve_ms);
        mesh_t.push(build_ms + solve_ms);
        grid_t.push(grid_ms);
    }
    Row {
        vsm_ms: median(vsm_t),
        mesh_v,
        mesh_dof,
        mesh_build_ms: median(build_t),
        mesh_solve_ms: median(solve_t),
        mesh_ms: median(mesh_t),
        mesh_folds,
        grid_v,
        grid_dof,
        grid_ms: median(grid_t),
        grid_folds,
    }
}

fn machine() -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    format!("machine: {cores} cores available (nproc), {cpu}")
}

fn main() {
    // `cargo bench` passes `--bench`; a name filter selects cases, as criterion would.
    let filter: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    println!("{}", machine());
    println!(
        "paper: Windows 7, Intel i7 2.8 GHz, 8 GB, C++ with CGAL and Lapack++ (Li et al., §6)"
    );
    println!("median of {REPEATS} runs after one warm-up; ms; (paper's figure in brackets)");
    let mut rows = Vec::new();
    for (i, (paper, kind)) in PAPER.iter().enumerate() {
        if !filter.is_empty()
            && !filter
                .iter()
                .any(|f| paper.name.to_lowercase().contains(&f.to_lowercase()))
        {
            continue;
        }
        let image = draw(*kind, paper.size, 0x5eed_0000 + i as u64);
        let target = Size::new(paper.target.0, paper.target.1).expect("target");
        if let Ok(dir) = std::env::var("PAPER_TABLES_DIR") {
            save(
                &image,
                &format!("{dir}/{}.png", paper.name.replace(' ', "-")),
            );
        }
        rows.push((paper, measure(&image, target)));
    }

    println!();
    println!(
        "Table 1: mesh deformation = mesh (or grid) construction + solve; not VSM, not render"
    );
    println!(
        "{:<15} {:>20} | {:>12} {:>13} {:>13} | {:>11} {:>12} {:>11} {:>7} {:>7} | {:>6} {:>6}",
        "case",
        "size -> target",
        "grid V",
        "grid DOF",
        "grid ms",
        "mesh V",
        "mesh DOF",
        "mesh ms",
        "build",
        "solve",
        "DOF<",
        "time<"
    );
    let (mut dof_wins, mut time_wins) = (0, 0);
    for (p, r) in &rows {
        let dof_win = r.mesh_dof < r.grid_dof;
        let time_win = r.mesh_ms < r.grid_ms;
        dof_wins += dof_win as usize;
        time_wins += time_win as usize;
        println!(
            "{:<15} {:>20} | {:>12} {:>13} {:>13} | {:>11} {:>12} {:>11} {:>7.1} {:>7.1} | {:>6} {:>6}",
            p.name,
            format!("{}x{} -> {}x{}", p.size.0, p.size.1, p.target.0, p.target.1),
            format!("{} ({})", r.grid_v, p.grid_v),
            format!("{} ({})", r.grid_dof, p.grid_dof),
            format!("{:.1} ({:.0})", r.grid_ms, p.grid_ms),
            format!("{} ({})", r.mesh_v, p.mesh_v),
            format!("{} ({})", r.mesh_dof, p.mesh_dof),
            format!("{:.1} ({:.0})", r.mesh_ms, p.mesh_ms),
            r.mesh_build_ms,
            r.mesh_solve_ms,
            if dof_win { "yes" } else { "NO" },
            if time_win { "yes" } else { "NO" },
        );
        if r.mesh_folds + r.grid_folds > 0 {
            println!(
                "  folded triangles reached the output: mesh {}, grid {}",
                r.mesh_folds, r.grid_folds
            );
        }
    }
    println!(
        "mesh below grid: DOF at {dof_wins} of {n} sizes, time at {time_wins} of {n}",
        n = rows.len()
    );
    let ratio = |f: &dyn Fn(&Row) -> f64, g: &dyn Fn(&Paper) -> f64| -> (f64, f64) {
        let ours: f64 = rows.iter().map(|(_, r)| f(r)).sum();
        let theirs: f64 = rows.iter().map(|(p, _)| g(p)).sum();
        (ours, theirs)
    };
    let (dof_m, dof_pm) = ratio(&|r| r.mesh_dof as f64, &|p| p.mesh_dof as f64);
    let (dof_g, dof_pg) = ratio(&|r| r.grid_dof as f64, &|p| p.grid_dof as f64);
    let (t_m, t_pm) = ratio(&|r| r.mesh_ms, &|p| p.mesh_ms);
    let (t_g, t_pg) = ratio(&|r| r.grid_ms, &|p| p.grid_ms);
    println!(
        "summed over the sizes: mesh/grid DOF {:.2} (paper {:.2}), mesh/grid time {:.2} (paper {:.2})",
        dof_m / dof_g,
        dof_pm / dof_pg,
        t_m / t_g,
        t_pm / t_pg
    );

    println!();
    println!("Table 2: VSM generation (ms)");
    println!(
        "{:<15} {:>10} {:>10} {:>12} {:>16}",
        "case", "canvas", "VSM", "paper VSM", "paper clutter"
    );
    for (p, r) in &rows {
        println!(
            "{:<15} {:>10} {:>10.1} {:>12.0} {:>16.0}",
            p.name,
            format!("{}x{}", p.size.0, p.size.1),
            r.vsm_ms,
            p.vsm_ms,
            p.clutter_ms
        );
    }
}

/// Writes a PNG for looking at the inputs (`PAPER_TABLES_DIR=dir`).
fn save(image: &Image, path: &str) {
    let enc =
        vizretarget::io::write_still(image, path.as_ref(), vizretarget::io::OutputFormat::Png);
    if let Err(e) = enc {
        eprintln!("{path}: {e}");
    }
}

// ---------------------------------------------------------------------------------------
// Drawing

/// xorshift64*: tiny, deterministic, good enough for placing marks.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1)
    }
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn f(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }
    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[(self.next() % items.len() as u64) as usize]
    }
}

/// Saturated mark colours (ColorBrewer / Tableau-like).
const MARKS: [[u8; 3]; 6] = [
    [215, 25, 28],
    [44, 123, 182],
    [26, 150, 65],
    [230, 97, 1],
    [123, 50, 148],
    [31, 119, 180],
];
/// Light region colours.
const PASTELS: [[u8; 3]; 8] = [
    [204, 235, 197],
    [222, 235, 247],
    [254, 230, 206],
    [239, 237, 245],
    [255, 255, 204],
    [229, 245, 224],
    [253, 224, 221],
    [224, 236, 244],
];
const GREY: [u8; 3] = [170, 170, 170];
const INK: [u8; 3] = [40, 40, 40];

struct Canvas {
    img: Image,
}

impl Canvas {
    fn new(w: u32, h: u32, bg: [u8; 3]) -> Canvas {
        Canvas {
            img: Image::filled(Size::new(w, h).expect("size"), [bg[0], bg[1], bg[2], 255]),
        }
    }
    fn w(&self) -> f64 {
        self.img.width() as f64
    }
    fn h(&self) -> f64 {
        self.img.height() as f64
    }

    fn blend(&mut self, x: i64, y: i64, c: [u8; 3], a: f32) {
        if x < 0 || y < 0 || x >= self.img.width() as i64 || y >= self.img.height() as i64 {
            return;
        }
        let p = self.img.get(x as u32, y as u32);
        let m = |d: u8, s: u8| (d as f32 * (1.0 - a) + s as f32 * a + 0.5) as u8;
        self.img.set(
            x as u32,
            y as u32,
            [m(p[0], c[0]), m(p[1], c[1]), m(p[2], c[2]), 255],
        );
    }

    fn rect(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, c: [u8; 3]) {
        for y in y0.round().max(0.0) as i64..y1.round().min(self.h()) as i64 {
            for x in x0.round().max(0.0) as i64..x1.round().min(self.w()) as i64 {
                self.blend(x, y, c, 1.0);
            }
        }
    }

    fn disc(&mut self, cx: f64, cy: f64, r: f64, c: [u8; 3]) {
        for y in (cy - r - 1.0).floor() as i64..=(cy + r + 1.0).ceil() as i64 {
            for x in (cx - r - 1.0).floor() as i64..=(cx + r + 1.0).ceil() as i64 {
                let d = (x as f64 + 0.5 - cx).hypot(y as f64 + 0.5 - cy);
                let a = (r + 0.5 - d).clamp(0.0, 1.0) as f32;
                if a > 0.0 {
                    self.blend(x, y, c, a);
                }
            }
        }
    }

    /// Pixels whose centres lie inside the polygon (even-odd).
    fn polygon(&mut self, pts: &[(f64, f64)], c: [u8; 3]) {
        let ymin = pts.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let ymax = pts.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
        let mut xs = Vec::new();
        for y in ymin.floor().max(0.0) as i64..ymax.ceil().min(self.h()) as i64 {
            let sy = y as f64 + 0.5;
            xs.clear();
            for (i, &(ax, ay)) in pts.iter().enumerate() {
                let (bx, by) = pts[(i + 1) % pts.len()];
                if (ay <= sy) != (by <= sy) {
                    xs.push(ax + (sy - ay) / (by - ay) * (bx - ax));
                }
            }
            xs.sort_by(f64::total_cmp);
            for s in xs.chunks_exact(2) {
                for x in (s[0] - 0.5).ceil().max(0.0) as i64..(s[1] - 0.5).ceil() as i64 {
                    self.blend(x, y, c, 1.0);
                }
            }
        }
    }

    /// An anti-aliased line (Wu), `alpha` opaque.
    fn line(&mut self, a: (f64, f64), b: (f64, f64), c: [u8; 3], alpha: f32) {
        let (mut a, mut b) = ((a.0 - 0.5, a.1 - 0.5), (b.0 - 0.5, b.1 - 0.5));
        let steep = (b.1 - a.1).abs() > (b.0 - a.0).abs();
        if steep {
            a = (a.1, a.0);
            b = (b.1, b.0);
        }
        if a.0 > b.0 {
            std::mem::swap(&mut a, &mut b);
        }
        let dx = b.0 - a.0;
        let g = if dx == 0.0 { 0.0 } else { (b.1 - a.1) / dx };
        for x in a.0.round() as i64..=b.0.round() as i64 {
            let y = a.1 + g * (x as f64 - a.0);
            let (yi, f) = (y.floor() as i64, (y - y.floor()) as f32);
            for (yy, cov) in [(yi, 1.0 - f), (yi + 1, f)] {
                if steep {
                    self.blend(yy, x, c, cov * alpha);
                } else {
                    self.blend(x, yy, c, cov * alpha);
                }
            }
        }
    }

    fn outline(&mut self, pts: &[(f64, f64)], c: [u8; 3]) {
        for i in 0..pts.len() {
            self.line(pts[i], pts[(i + 1) % pts.len()], c, 1.0);
        }
    }

    /// Text with its top-left at `(x, y)`, in the crate's bundled DejaVu Sans.
    fn text(&mut self, font: &FontRef<'_>, x: f64, y: f64, px: f32, s: &str, c: [u8; 3]) {
        let scale = PxScale::from(px);
        let sf = font.as_scaled(scale);
        let mut caret = x as f32;
        let base = y as f32 + sf.ascent();
        for ch in s.chars() {
            let id = sf.glyph_id(ch);
            let g = id.with_scale_and_position(scale, point(caret, base));
            caret += sf.h_advance(id);
            if let Some(o) = font.outline_glyph(g) {
                let bb = o.px_bounds();
                o.draw(|gx, gy, cov| {
                    self.blend(
                        bb.min.x as i64 + gx as i64,
                        bb.min.y as i64 + gy as i64,
                        c,
                        cov,
                    )
                });
            }
        }
    }
}

/// A wobbly closed outline around `(cx, cy)`.
fn blob(rng: &mut Rng, cx: f64, cy: f64, r: f64, n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            let rr = r * rng.f(0.65, 1.25);
            (cx + rr * a.cos(), cy + rr * 0.8 * a.sin())
        })
        .collect()
}

/// Mark centres and radii, at least `gap` radii sums apart, inside the canvas.
fn place(rng: &mut Rng, w: f64, h: f64, n: usize, r: (f64, f64), gap: f64) -> Vec<(f64, f64, f64)> {
    let mut out: Vec<(f64, f64, f64)> = Vec::new();
    let mut tries = 0;
    while out.len() < n && tries < 30_000 {
        tries += 1;
        let rr = rng.f(r.0, r.1);
        let (x, y) = (rng.f(rr + 6.0, w - rr - 6.0), rng.f(rr + 6.0, h - rr - 6.0));
        if out
            .iter()
            .all(|m| (x - m.0).hypot(y - m.1) > gap * (rr + m.2))
        {
            out.push((x, y, rr));
        }
    }
    out
}

/// Pastel land regions with grey borders.
fn map_regions(cv: &mut Canvas, rng: &mut Rng, n: usize, scale: f64) {
    let (w, h) = (cv.w(), cv.h());
    for _ in 0..n {
        let (cx, cy) = (rng.f(0.05, 0.95) * w, rng.f(0.1, 0.9) * h);
        let r = rng.f(0.08, 0.22) * w.min(h) * scale;
        let pts = blob(rng, cx, cy, r, 16);
        let c = rng.pick(&PASTELS);
        cv.polygon(&pts, c);
        cv.outline(&pts, GREY);
    }
}

fn graph_edges(cv: &mut Canvas, rng: &mut Rng, nodes: &[(f64, f64, f64)], reach: f64, p: f64) {
    for (i, a) in nodes.iter().enumerate() {
        for b in &nodes[i + 1..] {
            if (a.0 - b.0).hypot(a.1 - b.1) < reach && rng.f(0.0, 1.0) < p {
                cv.line((a.0, a.1), (b.0, b.1), [150, 150, 150], 0.8);
            }
        }
    }
}

fn draw(kind: Kind, (w, h): (u32, u32), seed: u64) -> Image {
    let font = FontRef::try_from_slice(include_bytes!("../assets/fonts/DejaVuSans-subset.ttf"))
        .expect("bundled font");
    let mut rng = Rng::new(seed);
    let (wf, hf) = (w as f64, h as f64);
    let mut cv = Canvas::new(w, h, [250, 250, 250]);
    match kind {
        Kind::ScatterMap => {
            map_regions(&mut cv, &mut rng, 8, 1.6);
            for (x, y, r) in place(&mut rng, wf, hf, 40, (5.0, 11.0), 3.0) {
                let c = rng.pick(&MARKS);
                cv.disc(x, y, r, c);
            }
            cv.text(&font, 12.0, 8.0, 16.0, "Cost of living index, 2017", INK);
        }
        Kind::GraphMap => {
            map_regions(&mut cv, &mut rng, 7, 1.5);
            let nodes = place(&mut rng, wf, hf, 45, (3.0, 7.0), 2.5);
            graph_edges(&mut cv, &mut rng, &nodes, 0.18 * wf, 0.35);
            for &(x, y, r) in &nodes {
                cv.disc(x, y, r, [44, 123, 182]);
            }
        }
        Kind::Communities => {
            for _ in 0..5 {
                let (cx, cy) = (rng.f(0.15, 0.85) * wf, rng.f(0.2, 0.8) * hf);
                let (rx, ry) = (rng.f(0.08, 0.18) * wf, rng.f(0.1, 0.25) * hf);
                let pts: Vec<(f64, f64)> = (0..48)
                    .map(|i| {
                        let a = std::f64::consts::TAU * i as f64 / 48.0;
                        (cx + rx * a.cos(), cy + ry * a.sin())
                    })
                    .collect();
                let c = rng.pick(&PASTELS);
                cv.polygon(&pts, c);
            }
            let nodes = place(&mut rng, wf, hf, 70, (5.0, 11.0), 3.0);
            graph_edges(&mut cv, &mut rng, &nodes, 0.25 * wf, 0.4);
            for &(x, y, r) in &nodes {
                let c = rng.pick(&MARKS);
                cv.disc(x, y, r, c);
            }
            for &(x, y, r) in nodes.iter().step_by(7) {
                cv.text(&font, x + r + 3.0, y - 7.0, 12.0, "Rust", INK);
            }
        }
        Kind::Infographic => {
            cv.rect(0.0, 0.0, wf, 70.0, [38, 70, 120]);
            cv.text(&font, 24.0, 18.0, 28.0, "World water use", [255, 255, 255]);
            for (i, label) in ["Farming", "Industry", "Homes"].iter().enumerate() {
                let y = 110.0 + i as f64 * 150.0;
                let c = MARKS[i];
                cv.disc(80.0, y + 40.0, 34.0, c);
                cv.disc(80.0, y + 40.0, 18.0, [255, 255, 255]);
                cv.text(&font, 140.0, y, 22.0, label, INK);
                let len = rng.f(0.3, 0.9) * (wf - 200.0);
                cv.rect(140.0, y + 36.0, 140.0 + len, y + 58.0, c);
                cv.text(
                    &font,
                    150.0 + len,
                    y + 38.0,
                    16.0,
                    &format!("{:.0} %", len / 5.0),
                    INK,
                );
                cv.line((24.0, y + 120.0), (wf - 24.0, y + 120.0), GREY, 1.0);
            }
            for k in 0..10 {
                let x = 40.0 + k as f64 * 60.0;
                cv.disc(x + 15.0, 600.0, 12.0, if k < 7 { MARKS[1] } else { GREY });
            }
            cv.text(&font, 24.0, 640.0, 13.0, "Source: a made-up survey", INK);
        }
        Kind::HexPoints => {
            let r = 9.0;
            let (dx, dy) = (r * 3f64.sqrt(), r * 1.5);
            let centres: Vec<(f64, f64, f64)> = (0..4)
                .map(|_| {
                    (
                        rng.f(0.15, 0.85) * wf,
                        rng.f(0.2, 0.8) * hf,
                        rng.f(40.0, 90.0),
                    )
                })
                .collect();
            let mut j = 0;
            while j as f64 * dy < hf + r {
                let y = j as f64 * dy;
                let off = if j % 2 == 0 { 0.0 } else { dx / 2.0 };
                let mut i = 0;
                while i as f64 * dx < wf + r {
                    let x = i as f64 * dx + off;
                    let d = centres
                        .iter()
                        .map(|c| ((x - c.0).hypot(y - c.1) / c.2).powi(2))
                        .fold(f64::INFINITY, f64::min);
                    let v = (-d).exp() + 0.25 * rng.f(0.0, 1.0) * (-d / 3.0).exp();
                    if v > 0.12 {
                        let t = v.min(1.0);
                        let c = [
                            (255.0 - 200.0 * t) as u8,
                            (245.0 - 150.0 * t) as u8,
                            (230.0 - 60.0 * t) as u8,
                        ];
                        let hex: Vec<(f64, f64)> = (0..6)
                            .map(|k| {
                                let a = std::f64::consts::PI / 6.0
                                    + k as f64 * std::f64::consts::PI / 3.0;
                                (x + (r - 0.6) * a.cos(), y + (r - 0.6) * a.sin())
                            })
                            .collect();
                        cv.polygon(&hex, c);
                    }
                    i += 1;
                }
                j += 1;
            }
            cv.line((30.0, hf - 30.0), (wf - 20.0, hf - 30.0), INK, 1.0);
            cv.line((30.0, 20.0), (30.0, hf - 30.0), INK, 1.0);
        }
        Kind::Graphs => {
            let nodes = place(&mut rng, wf, hf, 28, (6.0, 9.0), 3.0);
            graph_edges(&mut cv, &mut rng, &nodes, 0.3 * wf, 0.35);
            for (k, &(x, y, r)) in nodes.iter().enumerate() {
                cv.disc(x, y, r + 1.5, INK);
                cv.disc(x, y, r, MARKS[k % 3]);
            }
        }
        Kind::SocialNetwork => {
            let hubs: Vec<(f64, f64)> = place(&mut rng, wf, hf, 4, (55.0, 60.0), 1.2)
                .into_iter()
                .map(|(x, y, _)| (x, y))
                .collect();
            let mut nodes = Vec::new();
            for (k, &(hx, hy)) in hubs.iter().enumerate() {
                for _ in 0..18 {
                    let a = rng.f(0.0, std::f64::consts::TAU);
                    let d = rng.f(12.0, 60.0);
                    nodes.push((hx + d * a.cos(), hy + 0.8 * d * a.sin(), k));
                }
            }
            for &(x, y, k) in &nodes {
                let (hx, hy) = hubs[k];
                cv.line((hx, hy), (x, y), [180, 180, 180], 0.7);
            }
            for i in 0..hubs.len() {
                let j = (i + 1) % hubs.len();
                cv.line(hubs[i], hubs[j], [120, 120, 120], 1.0);
            }
            for &(x, y, k) in &nodes {
                cv.disc(x, y, 3.0, MARKS[k]);
            }
            for (k, &(x, y)) in hubs.iter().enumerate() {
                cv.disc(x, y, 7.0, MARKS[k]);
            }
        }
        Kind::HeatMap => {
            // A density heat map of users' locations over a map (the paper's Brightkite
            // heat map): smooth hot spots, yellow to red, over pastel regions.
            map_regions(&mut cv, &mut rng, 9, 1.6);
            let spots: Vec<(f64, f64, f64, f64)> = (0..14)
                .map(|_| {
                    (
                        rng.f(0.05, 0.95) * wf,
                        rng.f(0.1, 0.9) * hf,
                        rng.f(10.0, 45.0),
                        rng.f(0.4, 1.0),
                    )
                })
                .collect();
            for y in 0..h {
                for x in 0..w {
                    let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                    let v: f64 = spots
                        .iter()
                        .map(|&(cx, cy, s, a)| {
                            a * (-((px - cx).powi(2) + (py - cy).powi(2)) / (2.0 * s * s)).exp()
                        })
                        .sum();
                    if v > 0.05 {
                        let t = v.min(1.0);
                        let c = [255, (230.0 - 200.0 * t) as u8, (80.0 - 60.0 * t) as u8];
                        cv.blend(x as i64, y as i64, c, (0.25 + 0.6 * t) as f32);
                    }
                }
            }
            cv.text(&font, 16.0, 12.0, 18.0, "Check-ins per km²", INK);
        }
        Kind::RegionMap => {
            cv = Canvas::new(w, h, [236, 244, 250]);
            // One large land mass split into provinces, and a few islands.
            let land = blob(&mut rng, 0.5 * wf, 0.5 * hf, 0.42 * hf, 28);
            cv.polygon(&land, [250, 247, 235]);
            for _ in 0..14 {
                let (cx, cy) = (rng.f(0.3, 0.7) * wf, rng.f(0.25, 0.75) * hf);
                let r = rng.f(40.0, 90.0);
                let pts = blob(&mut rng, cx, cy, r, 12);
                let c = rng.pick(&PASTELS);
                cv.polygon(&pts, c);
                cv.outline(&pts, GREY);
            }
            cv.outline(&land, [120, 120, 120]);
            for (x, y, r) in place(&mut rng, wf, hf, 90, (4.0, 9.0), 3.0) {
                if (x - 0.5 * wf).hypot((y - 0.5 * hf) / 0.8) < 0.42 * hf {
                    cv.disc(x, y, r, [215, 25, 28]);
                }
            }
            cv.text(&font, 20.0, 16.0, 22.0, "Cities by population", INK);
        }
    }
    cv.img
}
