//! `flexbody::scenario::read_model_file` (what `Vehicle::read` and every
//! command read first): a model file (`model.toml`) with its `mesh` deck
//! and body files from the bundle. An accepted file must hold finite
//! numbers only, and the K, M and D assembled from its model finite
//! entries.
#![no_main]

use flexbody::fem::assembly::assemble;
use flexbody::scenario::read_model_file;
use flexbody_fuzz::{error_located, finite_debug, finite_values, Bundle, Lines};
use libfuzzer_sys::fuzz_target;

fuzz_target!(
    init: flexbody_fuzz::alloc_limit::set_memory_limit_from_env(),
    |data: &[u8]| {
        let bundle = Bundle::unpack(data, "model.toml");
        match read_model_file(&bundle.main) {
            Ok(file) => {
                finite_debug("the model file", &file);
                if let Ok(m) = assemble(&file.model) {
                    finite_values("K", m.stiffness.val());
                    finite_values("M", m.mass.val());
                    if let Some(d) = &m.damping {
                        finite_values("D", d.val());
                    }
                }
            }
            Err(e) => error_located(&e.to_string(), &bundle.dir, Lines::Required),
        }
    }
);
