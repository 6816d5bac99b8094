//! Helpers the hair-core integration tests share.

use hair_core::StrandSet;

/// The bits of every position and velocity coordinate, to compare runs bit for bit.
pub fn bits(strands: &StrandSet) -> Vec<u32> {
    strands
        .positions
        .iter()
        .chain(&strands.velocities)
        .flat_map(|v| v.iter().map(|c| c.to_bits()).collect::<Vec<_>>())
        .collect()
}
