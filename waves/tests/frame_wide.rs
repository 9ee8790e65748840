//! Frames wider than one skip chunk (the fast path of `dump_frame` skips unchanged values eight
//! at a time): a 21-variable frame, with sparse changes at any position, including the last
//! partial chunk, writes exactly what one `change_vector` per variable writes; a value too wide
//! for its variable is still refused wherever it sits.

use pmu50_waves::writer::{BitType, SigId, VcdBuilder, WriteError};
use pmu50_waves::{TimeUnit, Timescale};

const N: usize = 21;

fn builder() -> (VcdBuilder, Vec<SigId>) {
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "frame_wide test").unwrap();
    b.push_scope("top").unwrap();
    let ids = (0..N)
        .map(|k| {
            b.add_vector(BitType::Reg, &format!("v{k}"), 7, 0, 0)
                .unwrap()
        })
        .collect();
    b.pop_scope().unwrap();
    (b, ids)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 200, failure_persistence: None, ..Default::default() })]

    #[test]
    fn wide_frame_equals_single_changes(steps in proptest::collection::vec(proptest::collection::vec((0usize..N, 0u64..256), 0..4), 1..80)) {
        let (b1, ids1) = builder();
        let (b2, ids2) = builder();
        let mut w1 = b1.start(Vec::new()).unwrap();
        let mut w2 = b2.start(Vec::new()).unwrap();
        let mut f = w2.frame(&ids2).unwrap();
        let mut vals = [0u64; N];
        for (t, changes) in steps.into_iter().enumerate() {
            for (k, v) in changes {
                vals[k] = v;
            }
            w1.set_time(t as u64).unwrap();
            for (id, x) in ids1.iter().zip(vals) {
                w1.change_vector(*id, x).unwrap();
            }
            w2.dump_frame(&mut f, t as u64, &vals).unwrap();
        }
        let a = String::from_utf8(w1.finish().unwrap()).unwrap();
        let c = String::from_utf8(w2.finish().unwrap()).unwrap();
        proptest::prop_assert_eq!(a, c);
    }

    #[test]
    fn too_wide_value_is_refused_at_any_position(k in 0usize..N) {
        let (b, ids) = builder();
        let mut w = b.start(Vec::new()).unwrap();
        let mut f = w.frame(&ids).unwrap();
        let mut vals = [0u64; N];
        w.dump_frame(&mut f, 0, &vals).unwrap();
        w.dump_frame(&mut f, 1, &vals).unwrap();
        vals[k] = 256;
        let e = w.dump_frame(&mut f, 2, &vals).unwrap_err();
        let want = format!("top.v{k}");
        proptest::prop_assert!(matches!(&e, WriteError::ValueTooWide { name, value: 256, .. } if *name == want), "{:?}", e);
    }
}
