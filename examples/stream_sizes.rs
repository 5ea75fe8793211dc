//! Streaming at several scene sizes under one budget (issue 13, acceptance 3): what stays on the
//! GPU follows the budget, not the scene.
//!
//! ```text
//! cargo run --release --example stream_sizes -- --work /tmp/big --sizes 4,8,16 --budget-mib 256 --out results/
//! ```
//!
//! Makes (once, kept in `--work`) unique meshes: the scan `--mesh` (default the bunny of
//! `../shared/assets`) subdivided `--levels` times with its own seed per mesh, `--copies` copies
//! side by side (`subdivide_mesh.rs`), built into `.vgeo` files. For each size N it writes a scene
//! of the first N meshes on a grid with a camera path, streams it from the files under the
//! budget along `--frames` frames (a streaming step after each), and records the `.vgeo` bytes,
//! every scene GPU buffer (allocated), the page pool, the hierarchy (cluster locators, groups,
//! BVH), the resident page bytes (end and peak) and the bytes the last frame used; then a cold
//! camera cut (a new streamer, the path's close-up until settled: frames, resident against used
//! bytes). Writes
//! `sizes.json`, `sizes.md` and `sizes.svg` (MiB against the scene's `.vgeo` GiB) into `--out`.
//!
//! tests/streaming.rs runs `run` at a tiny scale.

#[allow(dead_code)]
#[path = "subdivide_mesh.rs"]
mod subdivide_mesh;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context as _, Result, bail};

/// What to run.
#[derive(Clone, Debug)]
pub struct Options {
    pub mesh: PathBuf,
    pub work: PathBuf,
    pub out: PathBuf,
    pub sizes: Vec<usize>,
    pub budget_bytes: u64,
    pub upload_bytes_per_frame: u64,
    pub levels: u32,
    pub copies: u32,
    pub frames: u32,
    pub width: u32,
    pub height: u32,
    /// The builder's triangle ratio of one simplification step.
    pub ratio: f32,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            mesh: Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/assets/scanned/bunny.ply"),
            work: std::env::temp_dir().join("vgeo-stream-sizes"),
            out: PathBuf::from("."),
            sizes: vec![4, 8, 16],
            budget_bytes: 256 << 20,
            upload_bytes_per_frame: 64 << 20,
            levels: 3,
            copies: 4,
            frames: 120,
            ratio: vgeo::BuildOptions::default().simplify_ratio,
            width: 1920,
            height: 1080,
        }
    }
}

/// One scene size's figures (bytes).
#[derive(Clone, Debug, serde::Serialize)]
pub struct SizeRecord {
    pub meshes: usize,
    pub vgeo_bytes: u64,
    pub triangles: u64,
    pub budget_bytes: u64,
    /// Every scene GPU buffer, allocated.
    pub gpu_bytes: u64,
    pub pool_bytes: u64,
    /// Cluster locators, groups and BVH nodes, allocated.
    pub hierarchy_bytes: u64,
    pub resident_bytes: u64,
    pub peak_resident_bytes: u64,
    pub used_bytes_last_frame: u64,
    pub uploads: u64,
    pub evictions: u64,
    /// (name, allocated bytes) per scene buffer.
    pub buffers: Vec<(String, u64)>,
    /// A cold camera cut: a new streamer with only the always-resident pages, the path's
    /// close-up rendered until a step stages, reads and evicts nothing (`None`: not within 64
    /// frames); then the resident bytes (always-resident pages and slots in use, whole: what the
    /// budget counts), the bytes of the pages that frame used (holding a cluster it drew), and
    /// the pages it still asked for (more than the budget holds).
    pub cold_frames_to_settle: Option<u32>,
    pub cold_resident_bytes: u64,
    pub cold_used_bytes: u64,
    pub cold_requests_left: u64,
    /// Where the cold cut's resident bytes go, against the pages it used
    /// ([`vgeo::Streamer::cut_residency`]).
    pub cold_residency: vgeo::CutResidency,
    /// The same per mesh (each mesh's `resident_bytes`: its resident pages' own bytes).
    pub cold_residency_by_mesh: Vec<vgeo::CutResidency>,
}

/// Mesh `i`'s `.vgeo` file name in `work`: it names the step ratio, so that a work folder made at
/// another ratio (0.5, the default before session 37) is not taken for this one.
fn vgeo_name(opts: &Options, i: usize) -> String {
    format!("m{i}-r{}.vgeo", opts.ratio)
}

/// Mesh `i`'s `.vgeo` in `work`, made if absent.
fn unique_mesh(opts: &Options, i: usize) -> Result<PathBuf> {
    let vgeo = opts.work.join(vgeo_name(opts, i));
    if vgeo.exists() {
        return Ok(vgeo);
    }
    let ply = opts.work.join(format!("m{i}.ply"));
    subdivide_mesh::write_subdivided(&opts.mesh, &ply, opts.levels, opts.copies, i as u64)?;
    let mesh = vgeo::merge_meshes(vgeo::load_meshes(&ply, &vgeo::ImportOptions::default())?);
    let build = vgeo::BuildOptions {
        simplify_ratio: opts.ratio,
        ..Default::default()
    };
    let built =
        vgeo::build(&mesh, &build).map_err(|e| anyhow::anyhow!("building mesh {i}: {e}"))?;
    let tmp = opts.work.join(format!("{}.part", vgeo_name(opts, i)));
    std::fs::write(&tmp, vgeo::save_vgeo(&built))?;
    std::fs::rename(&tmp, &vgeo)?;
    std::fs::remove_file(&ply)?;
    Ok(vgeo)
}

/// A scene of the first `n` meshes on a grid, with a path from above into a close-up and along.
fn scene_file(
    opts: &Options,
    n: usize,
    spacing: f32,
    scan: ([f32; 3], [f32; 3]),
) -> Result<PathBuf> {
    let mut s = String::new();
    for i in 0..n {
        let name = vgeo_name(opts, i);
        let _ = writeln!(s, "[[mesh]]\nname = \"m{i}\"\npath = \"{name}\"\n");
    }
    let cols = 4usize;
    for i in 0..n {
        let (x, z) = (
            (i % cols) as f32 * spacing,
            (i / cols) as f32 * spacing * 0.5,
        );
        let _ = writeln!(
            s,
            "[[instance]]\nmesh = \"m{i}\"\ntranslation = [{x}, 0, {z}]\n"
        );
    }
    // From above the grid into a close-up of the first mesh's first copy, then along the row.
    let (lo, hi) = scan;
    let c: [f32; 3] = std::array::from_fn(|k| (lo[k] + hi[k]) * 0.5);
    let d = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f32, f32::max);
    let far = spacing * 1.5;
    let _ = writeln!(
        s,
        "[[path]]\neye = [{far}, {fy}, {fz}]\ntarget = [{far}, {cy}, {tz}]\n\n[[path]]\neye = [{cx}, {ey}, {ez}]\ntarget = [{cx}, {cy}, {cz}]\n\n[[path]]\neye = [{ax}, {ey}, {ez}]\ntarget = [{ax}, {cy}, {cz}]\n",
        fy = far * 0.7,
        fz = far * 2.5,
        tz = far * 0.5,
        cx = c[0],
        cy = c[1],
        cz = c[2],
        ey = c[1] + 0.3 * d,
        ez = c[2] + 1.5 * d,
        ax = c[0] + 2.0 * spacing,
    );
    let path = opts.work.join(format!("s{n}.toml"));
    std::fs::write(&path, s)?;
    Ok(path)
}

/// A renderer streaming `meshes` under the options' budget, with `placements`' instances.
fn streamed_renderer(
    ctx: &vgeo::Context,
    opts: &Options,
    meshes: Vec<(vgeo::BuiltMesh, Box<dyn vgeo::PageSource>)>,
    placements: &[vgeo::Placement],
) -> Result<(vgeo::Renderer, vgeo::Streamer)> {
    let stream = vgeo::StreamOptions {
        budget_bytes: opts.budget_bytes,
        upload_bytes_per_frame: opts.upload_bytes_per_frame,
    };
    Ok(vgeo::Renderer::streamed(ctx, meshes, placements, stream)?)
}

/// One frame of a streamed renderer at `camera` (checked), then the streaming step after it.
fn stream_frame(
    r: &mut vgeo::Renderer,
    streamer: &mut vgeo::Streamer,
    opts: &Options,
    camera: &vgeo::Camera,
    light: &vgeo::Light,
) -> Result<vgeo::StreamStats> {
    let f = r.render(
        camera,
        opts.width,
        opts.height,
        &vgeo::FrameSettings::default(),
        vgeo::ViewMode::Lit,
        light,
    )?;
    f.check().map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(streamer.update(&mut r.scene)?)
}

/// Streams scene size `n` along its path; its record.
fn run_size(
    ctx: &vgeo::Context,
    opts: &Options,
    n: usize,
    spacing: f32,
    scan: ([f32; 3], [f32; 3]),
) -> Result<SizeRecord> {
    let file = scene_file(opts, n, spacing, scan)?;
    let streamed = vgeo::StreamedScene::load(&file, &|_| {})?;
    let vgeo_bytes: u64 = (0..n)
        .map(|i| std::fs::metadata(opts.work.join(vgeo_name(opts, i))).map(|m| m.len()))
        .sum::<std::io::Result<u64>>()?;
    let triangles = streamed.scene_triangles();
    let aspect = opts.width as f32 / opts.height as f32;
    let cameras = streamed
        .scene
        .path_cameras(&streamed.mesh_bounds(), aspect, opts.frames);
    let light = streamed.light;
    let (mut r, mut streamer) =
        streamed_renderer(ctx, opts, streamed.meshes, &streamed.placements)?;
    let (mut peak, mut uploads, mut evictions, mut last) = (0, 0, 0, None);
    for cam in &cameras {
        let st = stream_frame(&mut r, &mut streamer, opts, cam, &light)
            .with_context(|| format!("size {n}"))?;
        if let Some(e) = streamer.take_errors().first() {
            bail!("size {n}: {e}");
        }
        peak = peak.max(st.resident_bytes);
        uploads += st.uploads;
        evictions += st.evictions;
        last = Some(st);
    }
    let last = last.context("no frame")?;
    let memory = r.scene.memory();
    drop(streamer);
    drop(r);
    let cold = cold_cut(ctx, opts, &file)?;
    for (i, c) in cold.residency_by_mesh.iter().enumerate() {
        let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
        eprintln!(
            "  cold cut, mesh {i}: used {:.2} MiB, needed {:.2}, resident pages {:.2}, other {:.2}",
            mib(c.used_bytes),
            mib(c.needed_bytes),
            mib(c.resident_page_bytes),
            mib(c.other_bytes)
        );
    }
    let cap = |name: &str| {
        memory
            .buffers
            .iter()
            .filter(|b| b.name == name)
            .map(|b| b.capacity_bytes)
            .sum::<u64>()
    };
    Ok(SizeRecord {
        meshes: n,
        vgeo_bytes,
        triangles,
        budget_bytes: opts.budget_bytes,
        gpu_bytes: memory.capacity_bytes(),
        pool_bytes: cap("scene geometry pool"),
        hierarchy_bytes: cap("scene cluster locators") + cap("scene groups") + cap("scene bvh"),
        resident_bytes: last.resident_bytes,
        peak_resident_bytes: peak,
        used_bytes_last_frame: last.used_bytes,
        uploads,
        evictions,
        buffers: memory
            .buffers
            .iter()
            .map(|b| (b.name.to_string(), b.capacity_bytes))
            .collect(),
        cold_frames_to_settle: cold.frames_to_settle,
        cold_resident_bytes: cold.resident_bytes,
        cold_used_bytes: cold.used_bytes,
        cold_requests_left: cold.requests_left,
        cold_residency: cold.residency,
        cold_residency_by_mesh: cold.residency_by_mesh,
    })
}

/// What [`cold_cut`] measured (see [`SizeRecord`]'s `cold_` fields).
#[derive(Default)]
struct ColdCut {
    frames_to_settle: Option<u32>,
    resident_bytes: u64,
    used_bytes: u64,
    requests_left: u64,
    residency: vgeo::CutResidency,
    residency_by_mesh: Vec<vgeo::CutResidency>,
}

/// The scene in `file` streamed from scratch at its path's close-up (the middle keyframe):
/// frames until settled, then the resident page bytes, the bytes the settled frame used and the
/// pages it still asked for, and where the resident bytes go (in all and per mesh).
fn cold_cut(ctx: &vgeo::Context, opts: &Options, file: &Path) -> Result<ColdCut> {
    let streamed = vgeo::StreamedScene::load(file, &|_| {})?;
    let aspect = opts.width as f32 / opts.height as f32;
    let keys = streamed
        .scene
        .path_cameras(&streamed.mesh_bounds(), aspect, 3);
    let camera = *keys.get(1).context("the path has three keyframes")?;
    let light = streamed.light;
    let (mut r, mut streamer) =
        streamed_renderer(ctx, opts, streamed.meshes, &streamed.placements)?;
    for k in 1..=64u32 {
        let st = stream_frame(&mut r, &mut streamer, opts, &camera, &light).context("cold cut")?;
        if st.settled() {
            return Ok(ColdCut {
                frames_to_settle: Some(k),
                resident_bytes: st.resident_bytes,
                used_bytes: st.used_bytes,
                requests_left: st.requests,
                residency: streamer.cut_residency(),
                residency_by_mesh: streamer.cut_residency_by_mesh(),
            });
        }
    }
    Ok(ColdCut::default())
}

/// MiB against the scene's `.vgeo` GiB: GPU geometry allocated, page pool, resident pages,
/// hierarchy, and the budget.
fn svg(records: &[SizeRecord]) -> String {
    let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
    // The x axis in GiB, or MiB for small scenes.
    let big = records.iter().any(|r| r.vgeo_bytes >= 1 << 30);
    let (unit, scale) = if big { ("GiB", 30) } else { ("MiB", 20) };
    let gib = |b: u64| b as f64 / (1u64 << scale) as f64;
    let (w, h, m) = (640.0, 400.0, 60.0);
    let xmax = records
        .iter()
        .map(|r| gib(r.vgeo_bytes))
        .fold(0.0, f64::max)
        * 1.1;
    let ymax = records
        .iter()
        .map(|r| mib(r.gpu_bytes.max(r.budget_bytes)))
        .fold(0.0, f64::max)
        * 1.15;
    let px = |x: f64| m + x / xmax.max(1e-9) * (w - 2.0 * m);
    let py = |y: f64| h - m - y / ymax.max(1e-9) * (h - 2.0 * m);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<line x1=\"{m}\" y1=\"{b}\" x2=\"{r}\" y2=\"{b}\" stroke=\"black\"/>\n<line x1=\"{m}\" y1=\"{m}\" x2=\"{m}\" y2=\"{b}\" stroke=\"black\"/>\n<text x=\"{cx}\" y=\"{t}\" text-anchor=\"middle\">scene geometry on disk (.vgeo {unit})</text>\n<text x=\"14\" y=\"{cy}\" transform=\"rotate(-90 14 {cy})\" text-anchor=\"middle\">GPU MiB</text>\n",
        b = h - m,
        r = w - m,
        cx = w / 2.0,
        t = h - 15.0,
        cy = h / 2.0
    );
    for k in 0..=4 {
        let (x, y) = (xmax / 1.1 * k as f64 / 4.0, ymax / 1.15 * k as f64 / 4.0);
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{x:.2}</text>\n<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{y:.0}</text>",
            px(x),
            h - m + 16.0,
            m - 6.0,
            py(y) + 4.0
        );
    }
    let budget = mib(records.first().map_or(0, |r| r.budget_bytes));
    let _ = writeln!(
        s,
        "<line x1=\"{m}\" y1=\"{y:.1}\" x2=\"{r}\" y2=\"{y:.1}\" stroke=\"gray\" stroke-dasharray=\"6 4\"/><text x=\"{r}\" y=\"{t:.1}\" text-anchor=\"end\" fill=\"gray\">budget {budget:.0} MiB</text>",
        y = py(budget),
        r = w - m,
        t = py(budget) - 4.0
    );
    type Series = (&'static str, &'static str, fn(&SizeRecord) -> u64);
    let series: [Series; 4] = [
        ("GPU geometry allocated", "#c0392b", |r| r.gpu_bytes),
        ("page pool", "#2471a3", |r| r.pool_bytes),
        ("pages resident (end)", "#229954", |r| r.resident_bytes),
        ("hierarchy (locators, groups, BVH)", "#7d3c98", |r| {
            r.hierarchy_bytes
        }),
    ];
    for (k, (name, color, get)) in series.iter().enumerate() {
        let pts: Vec<String> = records
            .iter()
            .map(|r| format!("{:.1},{:.1}", px(gib(r.vgeo_bytes)), py(mib(get(r)))))
            .collect();
        let _ = writeln!(
            s,
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{color}\" stroke-width=\"2\"/>",
            pts.join(" ")
        );
        for p in &pts {
            let (x, y) = p.split_once(',').unwrap_or(("0", "0"));
            let _ = writeln!(
                s,
                "<circle cx=\"{x}\" cy=\"{y}\" r=\"3\" fill=\"{color}\"/>"
            );
        }
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{:.1}\" fill=\"{color}\">{name}</text>",
            m + 10.0,
            m + 14.0 + 16.0 * k as f64
        );
    }
    s.push_str("</svg>\n");
    s
}

/// The cold camera cut's table: what its columns mean, and its header.
const COLD_CUT_HEADER: &str = "\nA cold camera cut (a new streamer at the path's close-up until a step stages, reads and evicts nothing). *Resident*: the always-resident pages and the page slots in use, whole (what the budget counts). *Used*: the pages holding a cluster the settled frame drew (their own bytes). *Needed*: the smallest closed residency holding the used pages (the used pages, the DAG's groups above them up to the root that keep the cut crack-free, and the other groups those pages hold). *Other*: resident pages outside it (groups refined for a coarse cluster the frame drew, none of whose own members it then drew, all culled by the BVH nodes' frustum or HZB tests; the settled image needs them too). *Always resident*: every mesh's top pages, in view or not.\n\n| meshes | frames to settle | resident MiB | used MiB | resident / used | needed MiB | needed / used | other MiB | always resident MiB | slot rounding MiB | still asked |\n|---|---|---|---|---|---|---|---|---|---|---|\n";

/// One row of [`COLD_CUT_HEADER`]'s table.
fn cold_cut_row(r: &SizeRecord) -> String {
    let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
    let c = &r.cold_residency;
    let ratio = |a: u64| a as f64 / r.cold_used_bytes.max(1) as f64;
    format!(
        "| {} | {} | {:.2} | {:.2} | {:.2}x | {:.2} | {:.2}x | {:.2} | {:.2} | {:.2} | {} |\n",
        r.meshes,
        r.cold_frames_to_settle
            .map_or("not within 64".to_string(), |k| k.to_string()),
        mib(r.cold_resident_bytes),
        mib(r.cold_used_bytes),
        ratio(r.cold_resident_bytes),
        mib(c.needed_bytes),
        ratio(c.needed_bytes),
        mib(c.other_bytes),
        mib(c.fixed_bytes),
        mib(c.resident_bytes.saturating_sub(c.resident_page_bytes)),
        r.cold_requests_left
    )
}

/// Makes the meshes, streams every size, writes `sizes.json`, `sizes.md` and `sizes.svg`.
pub fn run(opts: &Options) -> Result<Vec<SizeRecord>> {
    let ctx = vgeo::Context::new(&vgeo::ContextOptions::from_env())?;
    run_on(&ctx, opts)
}

/// [`run`] on a context of the caller's.
pub fn run_on(ctx: &vgeo::Context, opts: &Options) -> Result<Vec<SizeRecord>> {
    let most = opts.sizes.iter().copied().max().unwrap_or(0);
    if most == 0 {
        bail!("--sizes needs at least one size above 0");
    }
    // The page pool is one storage buffer: say so before the meshes are made (minutes), not
    // when the first scene is loaded.
    let binds = ctx.caps().max_storage_buffer_range as u64;
    if opts.budget_bytes > binds {
        bail!(
            "--budget-mib {}: this device binds at most {} MiB in one buffer (maxStorageBufferRange), \
             and the page pool is one: give --budget-mib {} or less",
            opts.budget_bytes >> 20,
            binds >> 20,
            binds >> 20
        );
    }
    std::fs::create_dir_all(&opts.work)?;
    std::fs::create_dir_all(&opts.out)?;
    // A few meshes at once: subdividing is serial, and one build does not keep many cores busy.
    let next = std::sync::atomic::AtomicUsize::new(0);
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get().div_ceil(4));
    std::thread::scope(|s| -> Result<()> {
        let handles: Vec<_> = (0..workers.min(most))
            .map(|_| {
                s.spawn(|| -> Result<()> {
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        if i >= most {
                            return Ok(());
                        }
                        eprintln!("mesh {} of {most}", i + 1);
                        unique_mesh(opts, i)?;
                    }
                })
            })
            .collect();
        for h in handles {
            h.join()
                .map_err(|_| anyhow::anyhow!("a mesh-making thread panicked"))??;
        }
        Ok(())
    })?;
    // The grid's spacing: a little more than one mesh's width (its copies side by side in x).
    let scan = vgeo::merge_meshes(vgeo::load_meshes(
        &opts.mesh,
        &vgeo::ImportOptions::default(),
    )?);
    let (lo, hi) = scan.bounds().context("empty scan")?;
    let spacing = ((hi[0] - lo[0]) * 1.1 * opts.copies as f32).max(hi[2] - lo[2]) * 1.1;
    let mut records = Vec::new();
    for &n in &opts.sizes {
        eprintln!("scene of {n} meshes");
        records.push(run_size(ctx, opts, n, spacing, (lo, hi))?);
    }
    let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
    let mut md = format!(
        "# Streaming at {} scene sizes under {:.0} MiB\n\n{}x{}, {} frames along the path, {:.0} MiB per frame at most.\n\n| meshes | .vgeo GiB | triangles | GPU geometry MiB (allocated) | page pool MiB | hierarchy MiB | resident MiB (end) | peak resident MiB | used by the last frame MiB | uploads | evictions |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
        records.len(),
        mib(opts.budget_bytes),
        opts.width,
        opts.height,
        opts.frames,
        mib(opts.upload_bytes_per_frame)
    );
    for r in &records {
        let _ = writeln!(
            md,
            "| {} | {:.2} | {} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {} | {} |",
            r.meshes,
            r.vgeo_bytes as f64 / (1u64 << 30) as f64,
            r.triangles,
            mib(r.gpu_bytes),
            mib(r.pool_bytes),
            mib(r.hierarchy_bytes),
            mib(r.resident_bytes),
            mib(r.peak_resident_bytes),
            mib(r.used_bytes_last_frame),
            r.uploads,
            r.evictions,
        );
    }
    md.push_str(COLD_CUT_HEADER);
    for r in &records {
        md.push_str(&cold_cut_row(r));
    }
    std::fs::write(opts.out.join("sizes.md"), md)?;
    std::fs::write(
        opts.out.join("sizes.json"),
        serde_json::to_string_pretty(&records)?,
    )?;
    std::fs::write(opts.out.join("sizes.svg"), svg(&records))?;
    Ok(records)
}

/// A whole number of MiB above 0, in bytes.
fn mib_arg(flag: &str, v: &str) -> Result<u64> {
    v.parse::<u64>()
        .ok()
        .filter(|&m| m > 0)
        .and_then(|m| m.checked_mul(1 << 20))
        .with_context(|| format!("{flag} {v}: a whole number of MiB above 0"))
}

fn parse_args() -> Result<Options> {
    let mut o = Options::default();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().with_context(|| format!("{a} needs a value"));
        match a.as_str() {
            "--mesh" => o.mesh = value()?.into(),
            "--work" => o.work = value()?.into(),
            "--out" => o.out = value()?.into(),
            "--sizes" => {
                o.sizes = value()?
                    .split(',')
                    .map(|s| s.trim().parse())
                    .collect::<Result<_, _>>()?
            }
            "--budget-mib" => o.budget_bytes = mib_arg(&a, &value()?)?,
            "--mib-per-frame" => o.upload_bytes_per_frame = mib_arg(&a, &value()?)?,
            "--levels" => o.levels = value()?.parse()?,
            "--copies" => o.copies = value()?.parse()?,
            "--frames" => o.frames = value()?.parse()?,
            "--ratio" => o.ratio = value()?.parse()?,
            "--size" => {
                let v = value()?;
                let (x, y) = v.split_once('x').context("--size WxH")?;
                (o.width, o.height) = (x.parse()?, y.parse()?);
            }
            "--help" | "-h" => {
                println!(
                    "stream_sizes [--mesh SCAN] [--work DIR] [--out DIR] [--sizes 4,8,16] [--budget-mib 256] [--mib-per-frame 64] [--levels 3] [--copies 4] [--frames 120] [--size 1920x1080] [--ratio 0.35]\n\nStreams scenes of 4, 8, 16 unique meshes (made once in --work) under one budget and plots what stays on the GPU against the scene's size (sizes.md, sizes.json, sizes.svg in --out). The budget is at most what the device binds in one storage buffer (the page pool is one: 4 GiB on NVIDIA, 128 MiB on lavapipe), checked before any mesh is made."
                );
                std::process::exit(0);
            }
            other => bail!("unknown argument {other} (--help)"),
        }
    }
    Ok(o)
}

#[allow(dead_code)]
fn main() -> Result<()> {
    let opts = parse_args()?;
    for r in run(&opts)? {
        println!(
            "{} meshes, {:.2} GiB of .vgeo: GPU geometry {:.1} MiB, pool {:.1}, hierarchy {:.1}, resident {:.1} (peak {:.1})",
            r.meshes,
            r.vgeo_bytes as f64 / (1u64 << 30) as f64,
            r.gpu_bytes as f64 / (1u64 << 20) as f64,
            r.pool_bytes as f64 / (1u64 << 20) as f64,
            r.hierarchy_bytes as f64 / (1u64 << 20) as f64,
            r.resident_bytes as f64 / (1u64 << 20) as f64,
            r.peak_resident_bytes as f64 / (1u64 << 20) as f64
        );
        println!(
            "  cold cut: {} frames to settle, resident {:.2} MiB / used {:.2} MiB = {:.2}x (needed {:.2} MiB = {:.2}x, other {:.2}, always resident {:.2})",
            r.cold_frames_to_settle
                .map_or("not within 64".to_string(), |k| k.to_string()),
            r.cold_resident_bytes as f64 / (1u64 << 20) as f64,
            r.cold_used_bytes as f64 / (1u64 << 20) as f64,
            r.cold_resident_bytes as f64 / r.cold_used_bytes.max(1) as f64,
            r.cold_residency.needed_bytes as f64 / (1u64 << 20) as f64,
            r.cold_residency.needed_bytes as f64 / r.cold_used_bytes.max(1) as f64,
            r.cold_residency.other_bytes as f64 / (1u64 << 20) as f64,
            r.cold_residency.fixed_bytes as f64 / (1u64 << 20) as f64,
        );
    }
    println!("wrote {}", opts.out.join("sizes.svg").display());
    Ok(())
}
