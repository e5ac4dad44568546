//! `flexbody_io::deck::read_deck`: a CalculiX/Abaqus deck (`model.inp`)
//! with the `*INCLUDE` files of the bundle. An accepted deck must give a
//! model with finite numbers, and the K, M and D assembled from it finite
//! entries.
#![no_main]

use flexbody::fem::assembly::assemble;
use flexbody::io::deck::{read_deck, DeckOptions};
use flexbody_fuzz::{error_located, finite_debug, finite_values, Bundle, Lines};
use libfuzzer_sys::fuzz_target;

fuzz_target!(
    init: flexbody_fuzz::alloc_limit::set_memory_limit_from_env(),
    |data: &[u8]| {
        let bundle = Bundle::unpack(data, "model.inp");
        match read_deck(&bundle.main, &DeckOptions::default()) {
            Ok(deck) => {
                finite_debug("the deck's model", &deck.model);
                if let Ok(m) = assemble(&deck.model) {
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
