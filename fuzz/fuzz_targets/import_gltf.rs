#![no_main]
//! The .gltf importer: `vgeo::mesh::load_bytes(data, Format::Gltf, ..)`; see `vgeo_fuzz::import`.

use libfuzzer_sys::fuzz_target;
use vgeo::mesh::Format;

fuzz_target!(|data: &[u8]| {
    vgeo_fuzz::import(Format::Gltf, "fuzz.gltf", data);
});
