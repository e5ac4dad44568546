//! A fast hash for maps keyed by ids (node ids, DOFs): the multiply-rotate
//! hash of rustc's `FxHasher`. The keys come from the user's own model
//! files, so the DoS resistance of the standard SipHash buys nothing, and
//! it is several times slower on the 10^5 to 10^6 keys of a large mesh.

use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

/// A `HashMap` with [`IdHasher`].
pub type IdMap<K, V> = HashMap<K, V, BuildHasherDefault<IdHasher>>;

/// A `HashSet` with [`IdHasher`].
pub type IdSet<K> = HashSet<K, BuildHasherDefault<IdHasher>>;

/// An empty [`IdMap`] with room for `n` entries.
pub fn id_map<K, V>(n: usize) -> IdMap<K, V> {
    IdMap::with_capacity_and_hasher(n, Default::default())
}

#[derive(Default, Clone, Copy)]
pub struct IdHasher(u64);

const SEED: u64 = 0x51_7c_c1_b7_27_22_0a_95;

impl Hasher for IdHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(SEED);
    }

    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }

    fn write_isize(&mut self, x: isize) {
        self.write_u64(x as u64);
    }

    fn write_u8(&mut self, x: u8) {
        self.write_u64(x.into());
    }

    fn write_u32(&mut self, x: u32) {
        self.write_u64(x.into());
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Dof, DofKind};

    #[test]
    fn an_id_map_finds_what_it_holds() {
        let mut map = id_map(0);
        for node in 1..=10_000u64 {
            for kind in DofKind::ALL {
                map.insert(Dof::new(node * 7, kind), (node, kind.index()));
            }
        }
        assert_eq!(map.len(), 60_000);
        assert_eq!(map.get(&Dof::new(70, DofKind::Ry)), Some(&(10, 4)));
        assert_eq!(map.get(&Dof::new(71, DofKind::Ux)), None);
    }
}
