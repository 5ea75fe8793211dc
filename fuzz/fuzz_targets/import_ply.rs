#![no_main]
//! The .ply importer: `vgeo::mesh::load_bytes(data, Format::Ply, ..)`; see `vgeo_fuzz::import`.

use libfuzzer_sys::fuzz_target;
use vgeo::mesh::Format;

fuzz_target!(|data: &[u8]| {
    vgeo_fuzz::import(Format::Ply, "fuzz.ply", data);
});
