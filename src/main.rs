//! `vgeo`: the command-line front end. Thin: parses arguments and calls the library.

mod cli;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context as _, Result};
use clap::{Parser, Subcommand};
use vgeo::{
    Context, ContextOptions, FrameSettings, LoadedScene, Renderer as VgeoRenderer, ViewMode,
};

/// vgeo renders triangle scenes of any size at pixel-scale detail (Nanite-style cluster DAGs) on Vulkan.
///
/// With no command, renders the built-in demo scene (1,600 bunnies, 111 M instanced triangles) in
/// vgeo mode to `vgeo.png`, and its `clusters` view to `vgeo_clusters.png`.
///
/// Environment: VGEO_VALIDATION=1 enables the Khronos validation layer; VGEO_DEVICE=<substring>
/// picks a device by name; VGEO_SHADER_DIR=DIR is `--shader-dir DIR`; SHADER_DEBUG=1 (at build
/// time, or at run time for `--shader-dir`) embeds shader debug info for RenderDoc;
/// VGEO_PIPELINE_STATS=1 prints each pipeline's compiled statistics (registers, shared memory, ...)
/// where the driver has VK_KHR_pipeline_executable_properties (`vgeo info` says whether).
#[derive(Parser)]
#[command(name = "vgeo", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Compile the GLSL in DIR at start-up in place of the built-in shaders, without `cargo
    /// build`: DIR mirrors `shaders_glsl/` (copy a pass's file, e.g. `shade.comp.glsl`, or an
    /// include such as `common/shading.glsl`, and edit it); files not there are the built-in ones.
    /// A compile error names the file and line; an interface block whose size changed is refused.
    #[arg(long, global = true, value_name = "DIR")]
    shader_dir: Option<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a mesh (auto-framed) or a scene file (.toml) to a PNG.
    Render(RenderArgs),
    /// Build a mesh's cluster DAG into a .vgeo file, or every mesh of a scene file (.toml) with
    /// the scene's options.
    Build(cli::build::BuildArgs),
    /// Benchmark the scenes in the three modes (brute, lod, vgeo): speed, image error against a
    /// supersampled brute reference (--reference-spp), speed at equal error, scaling.
    Bench(vgeo::bench::BenchArgs),
    /// Check a .vgeo file: DAG invariants and crack-free cuts for many views (non-zero exit on failure).
    Verify(cli::build::VerifyArgs),
    /// Without FILE: the Vulkan device, driver and the features vgeo uses. With a .vgeo FILE: its stats.
    Info {
        /// A .vgeo file to describe.
        file: Option<PathBuf>,
    },
}

#[derive(clap::Args)]
struct RenderArgs {
    /// A mesh (.gltf .glb .obj .ply .stl .off) or a scene file (.toml).
    input: PathBuf,
    /// Output PNG.
    #[arg(short, long, default_value = "vgeo.png")]
    out: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1280)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 720)]
    height: u32,
    /// Rendering path: `brute` (every triangle, classic draws), `lod` (discrete LODs per mesh,
    /// one per instance chosen by projected error on the GPU, with frustum and HZB culling and
    /// multi-draw-indirect-count), `lod-cpu` (the same levels chosen on the CPU, one instanced
    /// draw per mesh and level) or `vgeo` (the cluster DAG, GPU-driven culling and LOD cut,
    /// visibility buffer).
    #[arg(long, default_value = "vgeo")]
    mode: String,
    /// Pixel error threshold of `--mode lod`, `lod-cpu` and `vgeo` (0 = full detail).
    #[arg(long, default_value_t = 1.0)]
    error_px: f32,
    /// What to show. Every mode: lit (the image: materials, textures, normal maps, one light plus
    /// ambient), albedo, normals, materials (a colour per material). `--mode vgeo` also: lambert
    /// (vertex normals, no materials), depth, triangles, clusters, instances, lod (DAG level),
    /// hwsw (which rasterizer drew it), groups (DAG group), overdraw (rasterizer writes per pixel),
    /// fallback (the fallback mesh: the DAG level nearest 2,000 triangles), residency (streaming:
    /// the pages of the group each drawn cluster would refine into; green resident, dark green
    /// absent but not needed at this threshold, amber requested this frame, red wanted but
    /// missing; all green without --geometry-budget).
    #[arg(long, default_value = "lit")]
    view: String,
    /// `--mode vgeo` rasterizer choice: auto (by the projected size of each cluster's triangles,
    /// see --hw-threshold), sw (compute) or hw (hardware). Clusters reaching the near plane always
    /// use hw.
    #[arg(long, default_value = "auto")]
    raster: String,
    /// `--mode vgeo`, the SW/HW split: a cluster goes to the hardware rasterizer when its
    /// triangles' edge-length equivalent exceeds this many pixels: sqrt(2 x their area-weighted
    /// mean area), the side of a square grid cell of that area (two triangles per cell), projected
    /// at the cluster's nearest point. Long thin triangles count by their area, not their length.
    /// 0: every cluster to hardware; 100000: software only (but the near plane's clusters).
    /// `auto`: chosen by measured cost, from the GPU times of the frames drawn (it starts at 64
    /// and tries its neighbours and software only over a few frames each; where nothing can be
    /// timed it stays at 64; no pixel changes, only the time).
    #[arg(long, default_value = "auto", value_parser = FrameSettings::parse_hw_threshold)]
    hw_threshold: f32,
    /// `--mode vgeo`: how the hardware rasterizer is fed: `mesh` (a mesh-shader workgroup per
    /// cluster, each vertex decoded once; needs VK_EXT_mesh_shader), `vertex` (vertex pulling,
    /// measured the faster on the H100 and lavapipe) or `auto` (vertex; `vgeo info` says which).
    #[arg(long, default_value = "auto")]
    hw_path: String,
    /// `--mode vgeo`: turn two-pass occlusion culling off.
    #[arg(long)]
    no_occlusion: bool,
    /// `--mode vgeo`: `emit_gbuffer` as `compute` (a dispatch per material, the default) or
    /// `raster` (a draw of tile quads per material against the material depth).
    #[arg(long, default_value = "compute")]
    emit: String,
    /// Frames to render (the same view); the last one is written and reported. With `--mode vgeo`
    /// the first frame has no previous depth to cull with, later ones do.
    #[arg(long, default_value_t = 1)]
    frames: u32,
    /// Print per-pass GPU times and counters.
    #[arg(long)]
    stats: bool,
    /// Capture the (last) frame with RenderDoc into FILE.rdc (also: VGEO_CAPTURE=FILE.rdc), through
    /// RenderDoc's in-application API: works when RenderDoc launched vgeo and when vgeo runs on its
    /// own with RenderDoc installed (Debian: `apt install renderdoc`). Open it in qrenderdoc; see
    /// docs/profiling.md.
    #[arg(long, value_name = "FILE.rdc")]
    capture: Option<PathBuf>,
    /// `--mode vgeo`: also write the `clusters` view of the same frame (a colour per cluster: the
    /// detail vgeo chose) to this PNG.
    #[arg(long, value_name = "FILE.png")]
    clusters_out: Option<PathBuf>,
    /// Instead of one view: a strip of `--panels` panels (each `--width` x `--height`, side by
    /// side) of the vgeo path, panel i with the camera 2^i times farther away, coloured by
    /// `--strip-view`. Each panel is magnified to the same apparent size (field of view narrowed by
    /// 2^i) while its LOD cut is the unmagnified view's at that distance (the threshold `--error-px`
    /// is scaled by 2^i with it), so the panels show how the cut coarsens with distance. Prints
    /// each panel's distance, clusters and triangles drawn (occlusion culling off; `--mode`,
    /// `--view` and `--frames` do not apply).
    #[arg(long)]
    lod_strip: bool,
    /// Panels of `--lod-strip` (1 to 16).
    #[arg(long, default_value_t = 5)]
    panels: u32,
    /// View of `--lod-strip`'s panels: clusters, lod, groups, triangles, hwsw, ... (any `--view`
    /// but fallback, which replaces the cut).
    #[arg(long, default_value = "clusters")]
    strip_view: String,
    /// `--mode vgeo`: stream the meshes' geometry pages under this GPU budget (MiB): only the
    /// pages the view needs stay resident, loaded on the GPU's requests between frames and
    /// evicted least-recently-used (use `--frames` to let the detail stream in; `--stats` prints
    /// each frame's residency, requests, uploads and evictions). `auto` (also the flag alone):
    /// a quarter of the device's largest device-local memory heap, at most what one storage
    /// buffer binds (the page pool is one), printed at the start. Without the flag: everything
    /// resident.
    #[arg(long, value_name = "MIB|auto", num_args = 0..=1, default_missing_value = "auto")]
    geometry_budget: Option<String>,
    /// With `--geometry-budget`: most page bytes read and uploaded between two frames (MiB).
    #[arg(long, value_name = "MIB", default_value_t = 16.0)]
    stream_mib_per_frame: f64,
    /// `--mode vgeo`: move the camera along the scene's path (its `[[path]]` keyframes, as `vgeo
    /// bench` does) over the `--frames` frames instead of holding the scene's camera; the image
    /// is the last frame's. With `--stats` and several frames, one line per frame (GPU ms, and
    /// with `--geometry-budget` the residency).
    #[arg(long)]
    path: bool,
    /// `--mode vgeo`: after the last frame, render its view N more times back to back in one
    /// submission (after about half a second of the same to let the GPU's clock rise, as `vgeo
    /// bench` times) and print the mean GPU ms: a frame time that does not depend on the clock
    /// falling between single frames. With `--geometry-budget`, the residency as the last frame
    /// left it (nothing streams meanwhile).
    #[arg(long, value_name = "N")]
    time: Option<u32>,
}

/// RenderDoc, loaded before any Vulkan instance when a capture is asked for.
static RENDERDOC: std::sync::OnceLock<vgeo::RenderDoc> = std::sync::OnceLock::new();

/// The capture file asked for: `--capture`, else `VGEO_CAPTURE`.
fn capture_path(a: &RenderArgs) -> Option<PathBuf> {
    a.capture.clone().or_else(|| {
        std::env::var_os("VGEO_CAPTURE")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    })
}

/// Loads RenderDoc and enables its Vulkan layer for the instance vgeo creates next.
fn load_renderdoc() -> Result<()> {
    let rd = vgeo::RenderDoc::load().map_err(|e| anyhow::anyhow!("--capture: {e}"))?;
    if !rd.launched_by_renderdoc() {
        // SAFETY: called from `main` before any other thread starts; the Vulkan loader reads it
        // when vgeo creates its instance.
        unsafe { std::env::set_var(vgeo::RenderDoc::LAYER_ENV, "1") };
    }
    let _ = RENDERDOC.set(rd);
    Ok(())
}

/// Runs `frame` as the captured frame when a capture was asked for.
fn captured<T>(
    a: &RenderArgs,
    ctx: &Context,
    what: &str,
    frame: impl FnOnce() -> Result<T>,
) -> Result<T> {
    let (Some(path), Some(rd)) = (capture_path(a), RENDERDOC.get()) else {
        return frame();
    };
    rd.start(ctx.vk_instance(), &path)
        .map_err(|e| anyhow::anyhow!("--capture: {e}"))?;
    let out = frame();
    let comments = format!(
        "vgeo {} {what}: {} {}x{}, --error-px {}",
        env!("CARGO_PKG_VERSION"),
        a.input.display(),
        a.width,
        a.height,
        a.error_px
    );
    let written = rd
        .end(ctx.vk_instance(), &path, &comments)
        .map_err(|e| anyhow::anyhow!("--capture: {e}"))?;
    eprintln!("captured one frame to {}", written.display());
    out
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Some(Command::Render(a)) = &cli.command
        && capture_path(a).is_some()
        && let Err(e) = load_renderdoc()
    {
        eprintln!("error: {e:#}");
        return ExitCode::FAILURE;
    }
    if let Some(dir) = &cli.shader_dir {
        // SAFETY: set before any other thread starts; every context reads it through
        // `ContextOptions::from_env`.
        unsafe { std::env::set_var("VGEO_SHADER_DIR", dir) };
    }
    let result = match cli.command {
        None => render(&RenderArgs {
            input: demo_scene(),
            out: PathBuf::from("vgeo.png"),
            width: 1280,
            height: 720,
            mode: "vgeo".into(),
            error_px: 1.0,
            view: "lit".into(),
            raster: "auto".into(),
            hw_threshold: FrameSettings::AUTO_HW_THRESHOLD,
            hw_path: "auto".into(),
            emit: "compute".into(),
            no_occlusion: false,
            frames: 1,
            stats: false,
            capture: None,
            clusters_out: Some(PathBuf::from("vgeo_clusters.png")),
            lod_strip: false,
            panels: 5,
            strip_view: "clusters".into(),
            geometry_budget: None,
            stream_mib_per_frame: 16.0,
            path: false,
            time: None,
        }),
        Some(Command::Render(a)) => render(&a),
        Some(Command::Build(a)) => cli::build::run_build(&a),
        Some(Command::Bench(a)) => vgeo::bench::run_bench(&a),
        Some(Command::Verify(a)) => match cli::build::run_verify(&a) {
            Ok(true) => Ok(()),
            Ok(false) => return ExitCode::FAILURE,
            Err(e) => Err(e),
        },
        Some(Command::Info { file: Some(f) }) => {
            vgeo::tools::info_vgeo(&f).map(|s| println!("{s}"))
        }
        Some(Command::Info { file: None }) => info(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// The demo scene: `assets/scenes/demo.toml` next to the working directory, else in the source tree.
fn demo_scene() -> PathBuf {
    let local = Path::new("assets/scenes/demo.toml");
    if local.exists() {
        return local.to_path_buf();
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/demo.toml")
}

fn context() -> Result<Context> {
    let mut opts = ContextOptions::from_env();
    let shader_dir = opts.shader_dir.take();
    let ctx = Context::new(&opts).context("cannot start Vulkan")?;
    // Under a capture tool (RenderDoc hides what it cannot capture), say what vgeo falls back to.
    let caps = ctx.caps();
    if !caps.tools.is_empty() {
        eprintln!("note: running under {}", caps.tools.join(", "));
        for f in &caps.fallbacks {
            eprintln!("note: {f}");
        }
    }
    if let Some(dir) = &shader_dir {
        let replaced = ctx
            .use_shader_dir(dir)
            .with_context(|| format!("--shader-dir {}", dir.display()))?;
        eprintln!(
            "shaders from {}: {}",
            dir.display(),
            if replaced.is_empty() {
                "none (no file there replaces a built-in one)".to_string()
            } else {
                replaced.join(", ")
            }
        );
    }
    Ok(ctx)
}

fn info() -> Result<()> {
    let ctx = context()?;
    println!("{}", ctx.caps());
    let hw = match vgeo::HwPath::Auto.resolve(ctx.caps()) {
        Ok(p) => p.name().to_string(),
        Err(e) => format!("({e})"),
    };
    println!("raster_hw path:        {hw} (--hw-path auto; mesh or vertex to choose)");
    Ok(())
}

fn render(a: &RenderArgs) -> Result<()> {
    if a.width == 0 || a.height == 0 || a.width > 16384 || a.height > 16384 {
        anyhow::bail!("--width and --height must be between 1 and 16384");
    }
    if !["brute", "lod", "lod-cpu", "vgeo"].contains(&a.mode.as_str()) {
        anyhow::bail!(
            "unknown --mode `{}` (available: brute, lod, lod-cpu, vgeo)",
            a.mode
        );
    }
    let view = ViewMode::parse(&a.view).with_context(|| {
        let names: Vec<_> = ViewMode::ALL
            .iter()
            .chain(ViewMode::MATERIAL.iter())
            .map(|m| m.name())
            .collect();
        format!(
            "unknown --view `{}` (available: {})",
            a.view,
            names.join(", ")
        )
    })?;
    let flags = match a.raster.as_str() {
        "auto" => 0,
        "sw" => FrameSettings::FORCE_SW,
        "hw" => FrameSettings::FORCE_HW,
        other => anyhow::bail!("unknown --raster `{other}` (available: auto, sw, hw)"),
    };
    if a.frames == 0 {
        anyhow::bail!("--frames must be at least 1");
    }
    let emit = vgeo::EmitPath::parse(&a.emit)
        .with_context(|| format!("unknown --emit `{}` (available: compute, raster)", a.emit))?;
    let hw_path = vgeo::HwPath::parse(&a.hw_path).with_context(|| {
        format!(
            "unknown --hw-path `{}` (available: auto, mesh, vertex)",
            a.hw_path
        )
    })?;
    if a.error_px.is_nan() || a.error_px < 0.0 || a.error_px.is_infinite() {
        anyhow::bail!("--error-px must be a finite number >= 0");
    }
    if a.lod_strip {
        return lod_strip(a, flags);
    }
    for (given, what) in [
        (
            a.geometry_budget.is_some(),
            "--geometry-budget streams vgeo's pages",
        ),
        (a.path, "--path renders vgeo frames along the scene's path"),
        (a.time.is_some(), "--time times vgeo frames back to back"),
    ] {
        if given && a.mode != "vgeo" {
            anyhow::bail!("{what}: it needs --mode vgeo");
        }
    }
    let t0 = std::time::Instant::now();
    let budget = a
        .geometry_budget
        .as_deref()
        .map(vgeo::GeometryBudget::parse)
        .transpose()
        .map_err(|e| anyhow::anyhow!("--geometry-budget: {e}"))?;
    if let Some(budget) = budget {
        // Streamed: `.vgeo` files are opened head-only and read page by page.
        let streamed = vgeo::StreamedScene::load(&a.input, &|line| eprintln!("{line}"))?;
        for w in &streamed.warnings {
            eprintln!("warning: {w}");
        }
        let camera = render_cameras(
            a,
            |aspect| {
                streamed
                    .scene
                    .path_cameras(&streamed.mesh_bounds(), aspect, a.frames)
            },
            streamed.camera(a.width, a.height),
        );
        let info = SceneSummary {
            meshes: streamed.scene.meshes.len(),
            instances: streamed.placements.len(),
            triangles: streamed.scene_triangles(),
        };
        let load_s = t0.elapsed().as_secs_f64();
        let ctx = context()?;
        let light = streamed.light;
        eprintln!("{}", budget.describe_on(ctx.caps()));
        let budget_bytes = budget.bytes_on(ctx.caps());
        let (r, streamer) = streamed_renderer(&ctx, streamed, budget_bytes, a)?;
        return render_vgeo(
            a,
            &ctx,
            r,
            Some(streamer),
            &camera,
            &light,
            &info,
            load_s,
            (view, flags, emit, hw_path),
        );
    }
    let loaded = LoadedScene::load(&a.input)?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    let camera = loaded.camera(a.width, a.height);
    let load_s = t0.elapsed().as_secs_f64();
    let ctx = context()?;
    if a.mode == "vgeo" {
        let camera = render_cameras(
            a,
            |aspect| {
                loaded
                    .scene
                    .path_cameras(&loaded.mesh_bounds(), aspect, a.frames)
            },
            camera,
        );
        let built = loaded.built_meshes(&|line| eprintln!("{line}"))?;
        let r = VgeoRenderer::new(&ctx, &built, &loaded.placements)?;
        let info = SceneSummary::of(&loaded);
        return render_vgeo(
            a,
            &ctx,
            r,
            None,
            &camera,
            &loaded.light,
            &info,
            load_s,
            (view, flags, emit, hw_path),
        );
    }
    let stats_lines = Vec::new();
    let shade = view.shade_mode().with_context(|| {
        format!(
            "--view {} needs --mode vgeo (brute and lod show: lit, albedo, normals, materials)",
            view.name()
        )
    })?;
    let (l, c) = (&loaded, &camera);
    let frame = match a.mode.as_str() {
        "lod" | "lod-cpu" => {
            let opts = vgeo::LodOptions::for_mode(&a.mode).unwrap_or_default();
            let lod = vgeo::LodRenderer::new(&ctx, &l.meshes(), &opts)?;
            lod.warnings()
                .iter()
                .for_each(|w| eprintln!("warning: {w}"));
            let size = (a.width, a.height);
            captured(a, &ctx, "lod frame", || {
                Ok(lod.render_view(&l.placements, c, &l.light, size, a.error_px, shade)?)
            })?
        }
        _ => {
            let brute = vgeo::BruteRenderer::new(&ctx, &l.meshes())?;
            brute
                .warnings()
                .iter()
                .for_each(|w| eprintln!("warning: {w}"));
            captured(a, &ctx, "brute frame", || {
                Ok(brute.render_view(&l.placements, c, &l.light, a.width, a.height, shade)?)
            })?
        }
    };
    finish(
        a,
        &ctx,
        &SceneSummary::of(&loaded),
        frame,
        load_s,
        &[],
        &stats_lines,
    )
}

/// The cameras of a vgeo render: with `--path`, `path(aspect)` (the scene's path over
/// `--frames`), else the scene's `camera`.
fn render_cameras(
    a: &RenderArgs,
    path: impl FnOnce(f32) -> Vec<vgeo::Camera>,
    camera: vgeo::Camera,
) -> Vec<vgeo::Camera> {
    if a.path {
        path(a.width as f32 / a.height.max(1) as f32)
    } else {
        vec![camera]
    }
}

/// Renders `a.frames` vgeo frames (streaming between them when a streamer is given) and reports
/// the last.
#[allow(clippy::too_many_arguments)]
fn render_vgeo(
    a: &RenderArgs,
    ctx: &Context,
    mut r: VgeoRenderer,
    mut streamer: Option<vgeo::Streamer>,
    cameras: &[vgeo::Camera],
    light: &vgeo::Light,
    info: &SceneSummary,
    load_s: f64,
    (view, flags, emit, hw_path): (ViewMode, u32, vgeo::EmitPath, vgeo::HwPath),
) -> Result<()> {
    let camera = *cameras.last().context("no camera")?;
    let mut stats_lines = Vec::new();
    r.set_emit_path(emit);
    r.set_hw_path(hw_path)
        .map_err(|e| anyhow::anyhow!("--hw-path {}: {e}", hw_path.name()))?;
    let settings = FrameSettings {
        error_px: a.error_px,
        hw_threshold_px: a.hw_threshold,
        flags,
        occlusion: !a.no_occlusion,
    };
    let mut last = None;
    for i in 0..a.frames {
        let mut frame = || {
            let cam = cameras.get(i as usize).unwrap_or(&camera);
            r.render(cam, a.width, a.height, &settings, view, light)
                .map_err(anyhow::Error::from)
        };
        last = Some(if i + 1 == a.frames {
            captured(a, ctx, "vgeo frame", frame)?
        } else {
            frame()?
        });
        let gpu_ms = last.as_ref().map_or(0.0, |f| f.frame.gpu_total_ms());
        if let Some(s) = streamer.as_mut() {
            let t = std::time::Instant::now();
            let st = s.update(&mut r.scene)?;
            let update_ms = t.elapsed().as_secs_f64() * 1e3;
            for e in s.take_errors() {
                eprintln!("warning: {e}");
            }
            if a.stats {
                let mib = |b: u64| b as f64 / (1 << 20) as f64;
                stats_lines.push(format!(
                    "  frame {}: {gpu_ms:.3} ms GPU; used {} pages ({:.2} MiB); then {} pages resident ({:.2} MiB), {} requested, {} staged ({:.2} MiB), {} reading, {} evicted (step {update_ms:.1} ms)",
                    i + 1,
                    st.used_pages,
                    mib(st.used_bytes),
                    st.resident_pages,
                    mib(st.resident_bytes),
                    st.requests,
                    st.uploads,
                    mib(st.upload_bytes),
                    st.reading,
                    st.evictions
                ));
            }
        } else if a.stats && a.frames > 1 {
            stats_lines.push(format!("  frame {}: {gpu_ms:.3} ms GPU", i + 1));
        }
    }
    let vf = last.context("no frame rendered")?;
    vf.check()
        .map_err(|e| anyhow::anyhow!("the frame is incomplete: {e}"))?;
    let mut summary = Vec::new();
    if let Some(n) = a.time.filter(|&n| n > 0) {
        let cams = vec![camera; n as usize];
        let t = std::time::Instant::now();
        while t.elapsed().as_secs_f64() < 0.5 {
            r.render_path_timed(&cams, a.width, a.height, &settings, view, light)?;
        }
        // The automatic split settles first and is held: no timed frame probes another.
        let mut settings = settings;
        if settings.auto_split() {
            let chosen =
                r.settle_split(&cams, a.width, a.height, &settings, view, light, 3000.0)?;
            let settled = if r.hw_split().1 {
                "settled"
            } else {
                "not settled in 3 s"
            };
            summary.push(format!("split:      auto: {chosen} px ({settled})"));
            settings.hw_threshold_px = chosen;
        }
        let times = r.render_path_timed(&cams, a.width, a.height, &settings, view, light)?;
        let mean = times
            .iter()
            .map(|p| p.iter().map(|x| x.1).sum::<f64>())
            .sum::<f64>()
            / times.len().max(1) as f64;
        summary.push(format!(
            "timed:      {mean:.3} ms GPU per frame (mean of {n} frames back to back, after a warm-up)"
        ));
    }
    let drawn_clusters: u32 = [&vf.main.counters, &vf.post.counters]
        .iter()
        .map(|c| c.sw_count + c.hw_count)
        .sum();
    summary.insert(0, format!("clusters:   {drawn_clusters} drawn"));
    if let Some(path) = &a.clusters_out {
        let cl = r.render(
            &camera,
            a.width,
            a.height,
            &settings,
            ViewMode::Clusters,
            light,
        )?;
        cl.frame.save_png(path)?;
        summary.push(format!("wrote {} (clusters view)", path.display()));
    }
    for (name, c) in [("main", &vf.main.counters), ("post", &vf.post.counters)] {
        // A frame without history: occluder_select ran (docs/architecture.md).
        let cold = if c.cold_groups_done > 0 {
            format!(
                " (no previous HZB: instances up to distance bin {} drawn first)",
                c.cold_cutoff
            )
        } else {
            String::new()
        };
        stats_lines.push(format!(
            "  {name}: instances {}/{} visible, {} BVH nodes, {} clusters tested, {} drawn ({} sw, {} of them small, {} smallest, {} hw), {} triangles; deferred {} inst / {} nodes / {} clusters; occluded {} inst / {} nodes / {} clusters",
            c.instances_visible,
            c.instances_tested,
            c.nodes_visited,
            c.clusters_tested,
            c.sw_count + c.hw_count,
            c.sw_count,
            c.sw_small_count,
            c.sw_quarter_count,
            c.hw_count,
            c.triangles,
            c.post_instance_count,
            c.post_node_count,
            c.post_cluster_count,
            c.occluded_instances,
            c.occluded_nodes,
            c.occluded_clusters,
        ) + &cold);
    }
    stats_lines.push(format!(
        "  visibility buffer: {:?} path; raster_hw: {} path (--hw-path {}); geometry {:.1} MiB",
        r.vis_path(),
        r.hw_path().name(),
        hw_path.name(),
        r.scene.geometry_bytes() as f64 / (1 << 20) as f64
    ));
    // What the geometry buffers hold (the allocation grows by doubling): per buffer, used MiB.
    let mib = |b: u64| b as f64 / (1 << 20) as f64;
    let mem = r.scene.memory();
    let used: Vec<String> = mem
        .buffers
        .iter()
        .filter(|b| b.used_bytes > 0)
        .map(|b| format!("{} {:.2}", b.name, mib(b.used_bytes)))
        .collect();
    stats_lines.push(format!(
        "  scene buffers used (MiB): {} (all {:.1} used of {:.1} allocated)",
        used.join(", "),
        mib(mem.used_bytes()),
        mib(mem.capacity_bytes())
    ));
    finish(a, ctx, info, vf.frame, load_s, &summary, &stats_lines)
}

/// A vgeo renderer whose meshes stream their pages under `--geometry-budget` (`.vgeo` files from
/// the file, page by page; the other meshes from memory).
fn streamed_renderer(
    ctx: &Context,
    streamed: vgeo::StreamedScene,
    budget_bytes: u64,
    a: &RenderArgs,
) -> Result<(VgeoRenderer, vgeo::Streamer)> {
    let x = a.stream_mib_per_frame;
    if !(x.is_finite() && x > 0.0) {
        anyhow::bail!("--stream-mib-per-frame must be a positive number of MiB");
    }
    let opts = vgeo::StreamOptions {
        budget_bytes,
        upload_bytes_per_frame: (x * (1u64 << 20) as f64) as u64,
    };
    Ok(VgeoRenderer::streamed(
        ctx,
        streamed.meshes,
        &streamed.placements,
        opts,
    )?)
}

/// `render --lod-strip`: the strip PNG and one line per panel.
fn lod_strip(a: &RenderArgs, flags: u32) -> Result<()> {
    let view = ViewMode::parse(&a.strip_view)
        .with_context(|| format!("unknown --strip-view `{}`", a.strip_view))?;
    let opts = vgeo::tools::LodStripOptions {
        panels: a.panels,
        width: a.width,
        height: a.height,
        error_px: a.error_px,
        hw_threshold_px: a.hw_threshold,
        flags,
        view,
    };
    let ctx = context()?;
    let strip = vgeo::tools::render_lod_strip(&ctx, &a.input, &opts, &|l| eprintln!("{l}"))?;
    strip.frame.save_png(&a.out)?;
    println!("device:     {}", ctx.caps().device_name);
    println!(
        "lod strip:  {} panels of {}x{}, threshold {} px",
        a.panels, a.width, a.height, a.error_px
    );
    for line in strip.report() {
        println!("  {line}");
    }
    println!("wrote {}", a.out.display());
    let errors = ctx.validation_errors();
    if !errors.is_empty() {
        anyhow::bail!("{} Vulkan validation error(s) (see above)", errors.len());
    }
    Ok(())
}

/// What the report says of the scene rendered.
struct SceneSummary {
    meshes: usize,
    instances: usize,
    /// Full-detail triangles, instanced.
    triangles: u64,
}

impl SceneSummary {
    fn of(loaded: &LoadedScene) -> Self {
        Self {
            meshes: loaded.prepared.len(),
            instances: loaded.placements.len(),
            triangles: loaded.scene_triangles(),
        }
    }
}

/// Writes the image and prints the report of a render.
fn finish(
    a: &RenderArgs,
    ctx: &Context,
    scene: &SceneSummary,
    frame: vgeo::Frame,
    load_s: f64,
    summary: &[String],
    stats_lines: &[String],
) -> Result<()> {
    frame.save_png(&a.out)?;
    let scene_tris = scene.triangles;
    println!("device:     {}", ctx.caps().device_name);
    println!("resolution: {}x{} ({} mode)", a.width, a.height, a.mode);
    println!(
        "scene:      {} meshes, {} instances, {} triangles (loaded in {load_s:.2} s)",
        scene.meshes, scene.instances, scene_tris
    );
    println!(
        "triangles:  {} drawn ({:.1} % of the scene)",
        frame.triangles,
        100.0 * frame.triangles as f64 / scene_tris.max(1) as f64
    );
    for l in summary.iter().filter(|l| l.starts_with("clusters")) {
        println!("{l}");
    }
    println!("GPU time:   {:.3} ms", frame.gpu_total_ms());
    for l in summary
        .iter()
        .filter(|l| l.starts_with("split") || l.starts_with("timed"))
    {
        println!("{l}");
    }
    if a.stats {
        for (pass, ms) in &frame.gpu_ms {
            println!("  {pass:<22} {ms:.3} ms");
        }
        for l in stats_lines {
            println!("{l}");
        }
    }
    println!("wrote {}", a.out.display());
    for l in summary.iter().filter(|l| l.starts_with("wrote")) {
        println!("{l}");
    }
    let errors = ctx.validation_errors();
    if !errors.is_empty() {
        anyhow::bail!("{} Vulkan validation error(s) (see above)", errors.len());
    }
    Ok(())
}
