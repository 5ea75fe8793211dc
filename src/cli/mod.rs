//! The command line's own modules (the binary's, not the library's): argument structs and the
//! printing around library calls. No library module imports them.

pub mod build;
