#![no_main]
//! The .stl importer: `vgeo::mesh::load_bytes(data, Format::Stl, ..)`; see `vgeo_fuzz::import`.

use libfuzzer_sys::fuzz_target;
use vgeo::mesh::Format;

fuzz_target!(|data: &[u8]| {
    vgeo_fuzz::import(Format::Stl, "fuzz.stl", data);
});
