//! `vgeo`: the command-line front end. Thin: parses arguments and calls the library.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context as _, Result};
use clap::{Parser, Subcommand};
use vgeo::gpu::{Context, ContextOptions};
use vgeo::render::LoadedScene;

/// vgeo renders triangle scenes of any size at pixel-scale detail (Nanite-style cluster DAGs) on Vulkan.
///
/// With no command, renders the built-in demo scene to `vgeo.png`.
///
/// Environment: VGEO_VALIDATION=1 enables the Khronos validation layer; VGEO_DEVICE=<substring>
/// picks a device by name; SHADER_DEBUG=1 (at build time) embeds shader debug info for RenderDoc.
#[derive(Parser)]
#[command(name = "vgeo", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a mesh (auto-framed) or a scene file (.toml) to a PNG.
    Render(RenderArgs),
    /// Build a mesh's cluster DAG into a .vgeo file.
    Build(vgeo::cmd_build::BuildArgs),
    /// Check a .vgeo file: DAG invariants and crack-free cuts for many views (non-zero exit on failure).
    Verify(vgeo::cmd_build::VerifyArgs),
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
    /// Rendering path: `brute` (every triangle, classic draws) or `lod` (discrete LODs per mesh,
    /// one per instance chosen by projected error).
    #[arg(long, default_value = "brute")]
    mode: String,
    /// Pixel error threshold of `--mode lod`.
    #[arg(long, default_value_t = 1.0)]
    error_px: f32,
    /// Print per-pass GPU times and counters.
    #[arg(long)]
    stats: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => render(&RenderArgs {
            input: demo_scene(),
            out: PathBuf::from("vgeo.png"),
            width: 1280,
            height: 720,
            mode: "brute".into(),
            error_px: 1.0,
            stats: true,
        }),
        Some(Command::Render(a)) => render(&a),
        Some(Command::Build(a)) => vgeo::cmd_build::run_build(&a),
        Some(Command::Verify(a)) => match vgeo::cmd_build::run_verify(&a) {
            Ok(true) => Ok(()),
            Ok(false) => return ExitCode::FAILURE,
            Err(e) => Err(e),
        },
        Some(Command::Info { file: Some(f) }) => {
            vgeo::cmd_build::info_vgeo(&f).map(|s| println!("{s}"))
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
    Context::new(&ContextOptions::from_env()).context("cannot start Vulkan")
}

fn info() -> Result<()> {
    let ctx = context()?;
    println!("{}", ctx.caps());
    Ok(())
}

fn render(a: &RenderArgs) -> Result<()> {
    if a.width == 0 || a.height == 0 || a.width > 16384 || a.height > 16384 {
        anyhow::bail!("--width and --height must be between 1 and 16384");
    }
    if a.mode != "brute" && a.mode != "lod" {
        anyhow::bail!("unknown --mode `{}` (available: brute, lod)", a.mode);
    }
    if a.error_px.is_nan() || a.error_px < 0.0 || a.error_px.is_infinite() {
        anyhow::bail!("--error-px must be a finite number >= 0");
    }
    let t0 = std::time::Instant::now();
    let loaded = LoadedScene::load(&a.input)?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    let camera = loaded.camera(a.width, a.height);
    let load_s = t0.elapsed().as_secs_f64();
    let ctx = context()?;
    let (l, c) = (&loaded, &camera);
    let frame = match a.mode.as_str() {
        "lod" => {
            let opts = vgeo::baseline::lod::LodOptions::default();
            let lod = vgeo::baseline::lod::Lod::new(&ctx, &l.meshes, &opts)?;
            lod.render(&l.placements, c, &l.light, a.width, a.height, a.error_px)?
        }
        _ => {
            let brute = vgeo::baseline::brute::Brute::new(&ctx, &l.meshes)?;
            brute.render(&l.placements, c, &l.light, a.width, a.height)?
        }
    };
    frame.save_png(&a.out)?;
    println!("device:     {}", ctx.caps().device_name);
    println!("resolution: {}x{}", a.width, a.height);
    println!(
        "scene:      {} meshes, {} instances (loaded in {load_s:.2} s)",
        loaded.meshes.len(),
        loaded.placements.len()
    );
    println!("triangles:  {}", frame.triangles);
    println!("GPU time:   {:.3} ms", frame.gpu_total_ms());
    if a.stats {
        for (pass, ms) in &frame.gpu_ms {
            println!("  {pass:<12} {ms:.3} ms");
        }
    }
    println!("wrote {}", a.out.display());
    let errors = ctx.validation_errors();
    if !errors.is_empty() {
        anyhow::bail!("{} Vulkan validation error(s) (see above)", errors.len());
    }
    Ok(())
}
