//! Steps as CalculiX reads them: the model flexbody reduces is the one that
//! holds at the first `*FREQUENCY` step. Boundary conditions and loads of
//! steps after it change nothing of that model: they are skipped and
//! reported once. A `*STEP, PERTURBATION` frequency step after a loaded
//! step is refused: CalculiX adds the preload's stress stiffening there,
//! which a linear reduction of the unloaded body would miss.

use super::cards::{Card, Loc};
use crate::InputError;

/// Keywords of a step that load the structure (a preload for a following
/// perturbation step).
const LOADS: &[&str] = &["CLOAD", "DLOAD", "DSLOAD", "TEMPERATURE"];

/// Where the reader is among the steps.
#[derive(Default)]
pub(super) struct Steps {
    /// Inside `*STEP` ... `*END STEP`.
    pub in_step: bool,
    /// The current step's `*STEP` card has `PERTURBATION`.
    perturbation: bool,
    /// The current step has a `*FREQUENCY`: its line.
    frequency: Option<Loc>,
    /// The first frequency step has ended: its `*FREQUENCY` line.
    pub done: Option<Loc>,
    /// The first load of the current step: keyword and line.
    step_load: Option<(String, Loc)>,
    /// The first load of an earlier step: keyword and line.
    load: Option<(String, Loc)>,
}

/// What the reader does with a card, given the steps.
pub(super) enum StepAction {
    /// Read the card as usual.
    Read,
    /// Skip it: it comes after the first frequency step and changes nothing
    /// of its model.
    AfterFrequency,
}

impl Steps {
    /// Follows the steps through `card`; an error refuses a preloaded
    /// perturbation frequency step.
    pub fn see(
        &mut self,
        files: &super::cards::Files,
        card: &Card,
    ) -> Result<StepAction, InputError> {
        let k = card.keyword.as_str();
        let after = self.done.is_some()
            && (matches!(k, "BOUNDARY" | "STEP" | "ENDSTEP") || LOADS.contains(&k));
        match k {
            "STEP" => {
                self.in_step = true;
                self.perturbation = card.has("PERTURBATION");
                self.frequency = None;
                self.step_load = None;
            }
            "ENDSTEP" => {
                self.in_step = false;
                if self.done.is_none() {
                    self.done = self.frequency;
                }
                if self.frequency.is_none() {
                    self.load = self.load.take().or(self.step_load.take());
                }
            }
            "FREQUENCY" if self.in_step && self.done.is_none() => {
                if self.perturbation {
                    if let Some((load, at)) = &self.load {
                        return Err(files.error(
                            card.loc,
                            format!(
                                "*FREQUENCY in a *STEP, PERTURBATION after a loaded step (*{load} on {}): \
                                 CalculiX adds the preload's stress stiffening to this frequency step, \
                                 and flexbody reduces the unloaded body, so the answer would miss the \
                                 preload; remove PERTURBATION (or the loads) to reduce the unloaded body",
                                files.describe(*at)
                            ),
                        ));
                    }
                }
                self.frequency = Some(card.loc);
            }
            _ if self.in_step
                && self.done.is_none()
                && LOADS.contains(&k)
                && self.step_load.is_none()
                && !card.data.is_empty() =>
            {
                let keyword = card.display.trim_start_matches('*').to_string();
                self.step_load = Some((keyword, card.loc));
            }
            _ => {}
        }
        Ok(if after {
            StepAction::AfterFrequency
        } else {
            StepAction::Read
        })
    }
}
