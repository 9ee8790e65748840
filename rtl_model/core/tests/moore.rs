//! All top-level outputs are Moore (docs/spec.md section 1): no input reaches an output in the
//! same cycle. For reachable register states (random parameters, random input histories with key
//! on/off runs, Vs2 good/bad, comparator changes and bus writes), the outputs that `eval` reports
//! for the cycle are the same for any two input vectors, and equal to `ports` of the registers.

mod common;

use common::{Driver, Rng};
use pmu50_core::pmu50::{eval, ports};
use pmu50_core::register_file::addr;
use pmu50_core::{Inputs, Params, Pmu50, TracedStep};
use proptest::prelude::*;

fn check_moore(m: &Pmu50, rng: &mut Rng) {
    let s = m.structural();
    let r = m.regs();
    let want = ports(&s, r);
    assert_eq!(m.peek(), want);
    let i1 = common::random_inputs(rng);
    let i2 = common::random_inputs(rng);
    let o1 = eval(&s, r, &i1).0;
    let o2 = eval(&s, r, &i2).0;
    assert_eq!(
        o1, want,
        "outputs under {i1:?} differ from the registers' decode"
    );
    assert_eq!(
        o2, want,
        "outputs under {i2:?} differ from the registers' decode"
    );
}

proptest! {
    #![proptest_config(common::cases(96))]

    #[test]
    fn no_input_reaches_an_output_combinationally(p in common::params(300, 700), seed in any::<u64>(), len in 0u64..6000) {
        let mut m = Pmu50::new(p).unwrap();
        let mut rng = Rng(seed ^ 0x5555);
        let mut d = Driver::new(seed);
        check_moore(&m, &mut rng);
        for _ in 0..len {
            let i = d.next(&m.peek());
            let TracedStep { after, .. } = m.step_traced(&i);
            prop_assert_eq!(after, m.peek());
            check_moore(&m, &mut rng);
        }
        // The read port too: `bus_rdata` of this cycle does not depend on this cycle's address.
        let mut a = m.clone();
        let mut b = m.clone();
        let x = a.step_traced(&Inputs { bus_addr: addr::ID, ..Default::default() }).before;
        let y = b.step_traced(&Inputs { bus_addr: addr::STATUS, bus_we: true, bus_wdata: 0xFFFF, ig: true, ..Default::default() }).before;
        prop_assert_eq!(x, y);
    }
}

/// The defaults, with key-on and key-off phases of the patent's lengths.
#[test]
fn defaults_are_moore_across_key_cycles() {
    let mut m = Pmu50::new(Params::default()).unwrap();
    let mut rng = Rng(7);
    let mut d = Driver::new(8);
    for _ in 0..20_000 {
        let i = d.next(&m.peek());
        m.step(&i);
        check_moore(&m, &mut rng);
    }
}
