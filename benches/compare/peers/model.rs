//! The Rust model in this process, untraced: one replay of the stimulus from reset through the
//! readable specification (`Pmu50Spec`) or the fast kernel (`Pmu50`), folded into the checksum.

use crate::stim::{mix, Stim};
use pmu50_core::{Pmu50, Pmu50Spec};

/// One replay through the readable specification; the checksum of its outputs.
#[inline(never)]
pub fn pass_spec(st: &Stim) -> u64 {
    let mut m = Pmu50Spec::new(st.params).expect("legal parameters");
    st.inputs.iter().fold(0, |h, i| mix(h, &m.step(i)))
}

/// One replay through the fast kernel; the checksum of its outputs.
#[inline(never)]
pub fn pass_kernel(st: &Stim) -> u64 {
    let mut m = Pmu50::new(st.params).expect("legal parameters");
    st.inputs.iter().fold(0, |h, i| mix(h, &m.step(i)))
}
