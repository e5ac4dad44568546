//! `flexbody_export::read_json_with_nodes`: a JSON reduced body
//! (`body.json`) and its mesh's nodes. An accepted body and its nodes must
//! hold finite numbers only.
#![no_main]

use flexbody::export::read_json_with_nodes;
use flexbody_fuzz::{error_located, finite_debug, Bundle, Lines};
use libfuzzer_sys::fuzz_target;

fuzz_target!(
    init: flexbody_fuzz::alloc_limit::set_memory_limit_from_env(),
    |data: &[u8]| {
        let bundle = Bundle::unpack(data, "body.json");
        match read_json_with_nodes(&bundle.main) {
            Ok((body, nodes)) => {
                finite_debug("the body", &body);
                finite_debug("the nodes", &nodes);
            }
            Err(e) => error_located(&e.to_string(), &bundle.dir, Lines::Required),
        }
    }
);
