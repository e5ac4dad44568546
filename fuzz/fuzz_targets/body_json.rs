//! `flexbody_export::read_json`: a JSON reduced body (`body.json`). An
//! accepted body must hold finite numbers only.
#![no_main]

use flexbody::export::read_json;
use flexbody_fuzz::{error_located, finite_debug, Bundle, Lines};
use libfuzzer_sys::fuzz_target;

fuzz_target!(
    init: flexbody_fuzz::alloc_limit::set_memory_limit_from_env(),
    |data: &[u8]| {
        let bundle = Bundle::unpack(data, "body.json");
        match read_json(&bundle.main) {
            Ok(body) => finite_debug("the body", &body),
            Err(e) => error_located(&e.to_string(), &bundle.dir, Lines::Required),
        }
    }
);
