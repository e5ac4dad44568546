//! `flexbody_export::mtx::read_mtx`: a Matrix Market body folder
//! (`index.json`, the main file, and the matrices it names). An accepted
//! body must hold finite numbers only. Errors about how the files fit
//! together name the file without a line.
#![no_main]

use flexbody::export::mtx::read_mtx;
use flexbody_fuzz::{error_located, finite_debug, Bundle, Lines};
use libfuzzer_sys::fuzz_target;

fuzz_target!(
    init: flexbody_fuzz::alloc_limit::set_memory_limit_from_env(),
    |data: &[u8]| {
        let bundle = Bundle::unpack(data, "index.json");
        match read_mtx(&bundle.dir) {
            Ok(body) => finite_debug("the body", &body),
            Err(e) => error_located(&e.to_string(), &bundle.dir, Lines::FileOnly),
        }
    }
);
