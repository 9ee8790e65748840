//! The reader tells FST from VCD by the first block type (0, FST_BL_HDR) and hands FST straight
//! to wellen under the panic guard: a complete FST reads back, a damaged one is an error (never
//! a panic, never an empty waveform), and a text file is still checked by the VCD validator.

use pmu50_waves::fst::start_fst;
use pmu50_waves::reader::{is_fst, ReadError, Waveform};
use pmu50_waves::writer::{BitType, VcdBuilder};
use pmu50_waves::{TimeUnit, Timescale};
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pmu50_waves_fst_read_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// An FST of one 8-bit counter counting 0..200 in steps of 1 us.
fn fst_bytes() -> Vec<u8> {
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "fst_read test").unwrap();
    b.push_scope("top").unwrap();
    let c = b.add_vector(BitType::Reg, "cnt", 7, 0, 0).unwrap();
    b.pop_scope().unwrap();
    // Tests run in parallel threads of one process: each FST gets a file of its own.
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let path = tmp(&format!(
        "cnt_{}.fst",
        N.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
    ));
    let mut w = start_fst(b, &path).unwrap();
    let mut f = w.frame(&[c]).unwrap();
    for k in 0..200u64 {
        w.dump_frame(&mut f, k, &[k]).unwrap();
    }
    w.finish().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    bytes
}

#[test]
fn complete_fst_reads_back() {
    let bytes = fst_bytes();
    assert!(is_fst(&bytes));
    let w = Waveform::from_bytes(bytes).unwrap();
    let ch = w.changes("top.cnt").unwrap();
    assert_eq!(ch.len(), 200);
    assert_eq!(ch[199].0, 199);
}

#[test]
fn damaged_fst_is_an_error_not_a_panic() {
    let bytes = fst_bytes();
    for cut in [1, 8, 40, bytes.len() / 2, bytes.len() - 3] {
        let r = Waveform::from_bytes(bytes[..cut].to_vec());
        assert!(
            r.is_err(),
            "FST cut to {cut} of {} bytes was read",
            bytes.len()
        );
    }
    let mut garbled = bytes.clone();
    for b in garbled.iter_mut().skip(400).step_by(3) {
        *b ^= 0x5a;
    }
    assert!(Waveform::from_bytes(garbled).is_err());
}

#[test]
fn text_still_goes_through_the_vcd_validator() {
    assert!(!is_fst(b"$timescale 1 us $end\n"));
    let e = Waveform::from_bytes(b"$timescale 1 us $end\n$bogus $end\n".to_vec()).unwrap_err();
    assert!(matches!(e, ReadError::Malformed { .. }), "{e:?}");
}
