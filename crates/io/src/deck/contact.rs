//! Tied contact: `*CONTACT PAIR, INTERACTION=` whose `*SURFACE
//! INTERACTION` has `*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=TIED` joins
//! its surfaces for good, which is a mesh tie. flexbody ties them exactly
//! (the limit of CalculiX's penalty stiffness K of the tied behaviour); any
//! other contact is nonlinear and refused, since ignoring it would change
//! the stiffness matrix.

use super::cards::{name, Card, Files, Loc};
use super::constraints::RawTie;
use super::keywords::Reader;
use crate::InputError;
use std::collections::BTreeMap;

/// A `*SURFACE INTERACTION`: whether its `*SURFACE BEHAVIOR` ties, and the
/// behaviour's line.
#[derive(Default)]
pub(super) struct Interaction {
    /// The `PRESSURE-OVERCLOSURE=` of its `*SURFACE BEHAVIOR`, upper case,
    /// with the card's line; `None` without one (hard contact).
    pub behavior: Option<(String, Loc)>,
    pub loc: Option<Loc>,
}

/// One slave-master pair of a `*CONTACT PAIR` card.
pub(super) struct RawContactPair {
    pub interaction: String,
    pub slave: String,
    pub master: String,
    /// `ADJUST=`: a distance within which slave nodes are moved onto the
    /// master surface.
    pub adjust: Option<f64>,
    pub loc: Loc,
}

/// The contact keywords read: the interactions by name (upper case) and
/// the pairs, with the interaction that `*SURFACE BEHAVIOR` refers to.
#[derive(Default)]
pub(super) struct Contact {
    pub interactions: BTreeMap<String, Interaction>,
    pub pairs: Vec<RawContactPair>,
    current: Option<String>,
}

impl Contact {
    /// A card other than an interaction's options ends the interaction.
    pub(super) fn end_interaction(&mut self) {
        self.current = None;
    }
}

impl Reader<'_> {
    /// `*SURFACE INTERACTION, NAME=`: the options after it (`*SURFACE
    /// BEHAVIOR`, `*FRICTION`) belong to it.
    pub(super) fn surface_interaction(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["NAME"]);
        let n = card.require_name(self.files, "NAME")?;
        self.contact.interactions.entry(n.clone()).or_default().loc = Some(card.loc);
        self.contact.current = Some(n);
        Ok(())
    }

    /// `*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=`: only `TIED` is read (its
    /// penalty stiffness is not needed: the tie is exact).
    pub(super) fn surface_behavior(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["PRESSURE-OVERCLOSURE"]);
        let Some(current) = self.contact.current.clone() else {
            return Err(self.files.error(
                card.loc,
                "*SURFACE BEHAVIOR must follow a *SURFACE INTERACTION card",
            ));
        };
        let kind = card
            .value("PRESSURE-OVERCLOSURE")
            .map_or_else(|| "HARD".to_string(), name);
        if let Some(i) = self.contact.interactions.get_mut(&current) {
            i.behavior = Some((kind, card.loc));
        }
        Ok(())
    }

    /// `*CONTACT PAIR, INTERACTION=, TYPE=[, ADJUST=][, SMALL SLIDING]`:
    /// `slave surface, master surface` lines.
    pub(super) fn contact_pair(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["INTERACTION", "TYPE", "ADJUST", "SMALLSLIDING"]);
        let interaction = card.require_name(self.files, "INTERACTION")?;
        if let Some(t) = card.value("TYPE").map(name) {
            if !matches!(
                t.replace(' ', "").as_str(),
                "NODETOSURFACE" | "SURFACETOSURFACE"
            ) {
                return Err(self.files.error(
                    card.loc,
                    format!(
                        "*CONTACT PAIR, TYPE={t}: only NODE TO SURFACE and SURFACE TO \
                         SURFACE pairs can be read (as ties)"
                    ),
                ));
            }
        }
        let adjust = match card.value("ADJUST") {
            None => None,
            Some(v) => Some(
                super::cards::parse_float(v)
                    .filter(|d| d.is_finite() && *d >= 0.0)
                    .ok_or_else(|| {
                        self.files.error(
                            card.loc,
                            format!(
                                "*CONTACT PAIR: ADJUST={v}: a distance >= 0 (a node set is \
                                 not supported)"
                            ),
                        )
                    })?,
            ),
        };
        if card.data.is_empty() {
            return Err(self.files.error(
                card.loc,
                "*CONTACT PAIR needs a line: slave surface, master surface",
            ));
        }
        for line in &card.data {
            let (Some(slave), Some(master)) = (line.get(0), line.get(1)) else {
                return Err(self.files.error(
                    line.loc,
                    "*CONTACT PAIR: give the slave surface and the master surface",
                ));
            };
            self.contact.pairs.push(RawContactPair {
                interaction: interaction.clone(),
                slave: name(slave),
                master: name(master),
                adjust,
                loc: line.loc,
            });
        }
        Ok(())
    }
}

/// The tied contact pairs as ties (named `contact pair k`); an error
/// refuses a pair whose interaction is not defined or does not tie.
pub(super) fn tied_pairs(files: &Files, contact: &Contact) -> Result<Vec<RawTie>, InputError> {
    let mut ties = Vec::with_capacity(contact.pairs.len());
    for (k, p) in contact.pairs.iter().enumerate() {
        let Some(interaction) = contact.interactions.get(&p.interaction) else {
            return Err(files.error(
                p.loc,
                format!(
                    "*CONTACT PAIR: surface interaction '{}' is not defined",
                    p.interaction
                ),
            ));
        };
        match &interaction.behavior {
            Some((kind, _)) if kind == "TIED" => {}
            other => {
                let said = match other {
                    Some((kind, loc)) => {
                        format!("PRESSURE-OVERCLOSURE={kind} ({})", files.describe(*loc))
                    }
                    None => "no *SURFACE BEHAVIOR (hard contact)".to_string(),
                };
                return Err(files.error(
                    p.loc,
                    format!(
                        "*CONTACT PAIR with interaction '{}': {said} is nonlinear contact, \
                         which is not supported (ignoring it would change the stiffness \
                         matrix); only tied contact (PRESSURE-OVERCLOSURE=TIED) is read",
                        p.interaction
                    ),
                ));
            }
        }
        ties.push(RawTie {
            name: format!("contact pair {}", k + 1),
            label: format!("*CONTACT PAIR {} (tied)", k + 1),
            slave: p.slave.clone(),
            master: p.master.clone(),
            tolerance: p.adjust,
            adjust: p.adjust.is_some(),
            loc: p.loc,
        });
    }
    Ok(ties)
}
