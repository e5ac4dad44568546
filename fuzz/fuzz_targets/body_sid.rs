//! `flexbody_export::read_sid`: a SID file (`body.sid`). An accepted SID
//! must hold finite numbers only.
#![no_main]

use flexbody::export::read_sid;
use flexbody_fuzz::{error_located, finite_debug, Bundle, Lines};
use libfuzzer_sys::fuzz_target;

fuzz_target!(
    init: flexbody_fuzz::alloc_limit::set_memory_limit_from_env(),
    |data: &[u8]| {
        let bundle = Bundle::unpack(data, "body.sid");
        match read_sid(&bundle.main) {
            Ok(sid) => finite_debug("the SID", &sid),
            Err(e) => error_located(&e.to_string(), &bundle.dir, Lines::Required),
        }
    }
);
