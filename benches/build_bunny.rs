//! Build-speed check: `cargo bench --bench build_bunny` (or `cargo run --release --bench build_bunny`)
//! builds the Stanford bunny and prints each phase's time and the input triangles per second.

fn main() {
    let dir = std::env::var("VGEO_SHARED_ASSETS").unwrap_or_else(|_| "/work/shared/assets".into());
    let path = std::path::Path::new(&dir).join("scanned/bunny.ply");
    let meshes = match vgeo::build_files::load_input(&path, &Default::default()) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{e:#}");
            std::process::exit(1);
        }
    };
    let threads: Option<usize> = std::env::args().nth(1).and_then(|a| a.parse().ok());
    for mesh in meshes {
        let t0 = std::time::Instant::now();
        let opts = vgeo::builder::BuildOptions {
            threads,
            ..Default::default()
        };
        let r = vgeo::builder::build_with_progress(&mesh, &opts, &|m| {
            eprintln!("{:8.3}s {m}", t0.elapsed().as_secs_f64())
        });
        let secs = t0.elapsed().as_secs_f64();
        match r {
            Ok(b) => println!(
                "{}: {} triangles in {secs:.3}s = {:.0} triangles/s ({} clusters)",
                mesh.name,
                mesh.triangle_count(),
                mesh.triangle_count() as f64 / secs,
                b.clusters.len()
            ),
            Err(e) => eprintln!("{e}"),
        }
    }
}
