//! `flexbody_io::matrices::read_calculix_matrices`: CalculiX's `job.sti`
//! (the main file), `job.mas` and `job.dof`. Accepted matrices must have
//! finite entries.
#![no_main]

use flexbody::io::matrices::read_calculix_matrices;
use flexbody_fuzz::{error_located, finite_debug, finite_values, Bundle, Lines};
use libfuzzer_sys::fuzz_target;

fuzz_target!(
    init: flexbody_fuzz::alloc_limit::set_memory_limit_from_env(),
    |data: &[u8]| {
        let bundle = Bundle::unpack(data, "job.sti");
        match read_calculix_matrices(&bundle.path("job")) {
            Ok(model) => {
                finite_values("K", model.stiffness.val());
                finite_values("M", model.mass.val());
                finite_debug("the DOF map", &model.dof_map);
            }
            Err(e) => error_located(&e.to_string(), &bundle.dir, Lines::Required),
        }
    }
);
