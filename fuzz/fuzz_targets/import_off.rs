#![no_main]
//! The .off importer: `vgeo::mesh::load_bytes(data, Format::Off, ..)`; see `vgeo_fuzz::import`.

use libfuzzer_sys::fuzz_target;
use vgeo::mesh::Format;

fuzz_target!(|data: &[u8]| {
    vgeo_fuzz::import(Format::Off, "fuzz.off", data);
});
