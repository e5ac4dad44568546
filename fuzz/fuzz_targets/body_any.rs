//! `flexbody_export::format::read_any` (what `flexbody inspect` reads):
//! the format recognised from the content of `body` (SID, JSON, or an
//! `index.json` pointing at its folder), or the bundle's folder when it
//! has an `index.json`. An accepted body must hold finite numbers only.
#![no_main]

use flexbody::export::read_any;
use flexbody_fuzz::{error_located, finite_debug, Bundle, Lines};
use libfuzzer_sys::fuzz_target;

fuzz_target!(
    init: flexbody_fuzz::alloc_limit::set_memory_limit_from_env(),
    |data: &[u8]| {
        let bundle = Bundle::unpack(data, "body");
        let path = if bundle.has("index.json") {
            bundle.dir.clone()
        } else {
            bundle.main.clone()
        };
        match read_any(&path) {
            Ok(body) => finite_debug("the body", &body),
            Err(e) => error_located(&e.to_string(), &bundle.dir, Lines::FileOnly),
        }
    }
);
