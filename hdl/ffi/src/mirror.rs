//! The C ABI mirror of the core's inputs, outputs and internals, generated from the signal table
//! (`pmu50_core::signals`): one C struct field per signal, in table order, each the smallest of
//! `uint8_t`/`uint16_t`/`uint32_t`/`uint64_t` that holds the signal's widest value (a
//! structural width at its maximum), laid out by the C rules (each field aligned to its size, the
//! struct's size a multiple of its largest field). The Rust side stores the bytes and reads and
//! writes them at the computed offsets; [`c_structs`] writes the same structs as C, and a test
//! (`hdl/ffi/tests/header.rs`) checks that `include/pmu50.h` contains exactly that text. No
//! signal name or width is written here.

use pmu50_core::signals::{self, Signal, N_INPUTS, N_INTERNALS, N_OUTPUTS, N_REGISTERS};
use pmu50_core::{Inputs, Internals, Outputs};
use std::fmt;

/// Bytes of the C field that holds `bits` bits.
pub const fn c_size(bits: u8) -> usize {
    if bits <= 8 {
        1
    } else if bits <= 16 {
        2
    } else if bits <= 32 {
        4
    } else {
        8
    }
}

/// The C type of a field of `bytes` bytes.
pub const fn c_type(bytes: usize) -> &'static str {
    match bytes {
        1 => "uint8_t",
        2 => "uint16_t",
        4 => "uint32_t",
        _ => "uint64_t",
    }
}

/// C layout of a struct with one field per signal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout<const N: usize> {
    pub offset: [usize; N],
    pub size: [usize; N],
    pub total: usize,
    pub align: usize,
}

/// The C layout of `list` (N = `list.len()`).
pub const fn layout<T, const N: usize>(list: &[Signal<T>]) -> Layout<N> {
    assert!(list.len() == N);
    let mut offset = [0; N];
    let mut size = [0; N];
    let mut at: usize = 0;
    let mut align: usize = 1;
    let mut k = 0;
    while k < N {
        let sz = c_size(list[k].width.max_bits());
        at = at.div_ceil(sz) * sz;
        offset[k] = at;
        size[k] = sz;
        at += sz;
        if sz > align {
            align = sz;
        }
        k += 1;
    }
    Layout {
        offset,
        size,
        total: at.div_ceil(align) * align,
        align,
    }
}

pub const INPUT_LAYOUT: Layout<N_INPUTS> = layout(signals::INPUTS);
pub const OUTPUT_LAYOUT: Layout<N_OUTPUTS> = layout(signals::OUTPUTS);
pub const INTERNAL_LAYOUT: Layout<N_INTERNALS> = layout(signals::INTERNALS);

// The `align` attributes below must be the layouts' alignment (C's alignment of the struct).
const _: () = assert!(
    INPUT_LAYOUT.align == 2 && OUTPUT_LAYOUT.align == 2 && INTERNAL_LAYOUT.align == 1,
    "update the #[repr(align)] of the C mirror structs"
);

fn read(bytes: &[u8], at: usize, size: usize) -> u64 {
    let mut b = [0u8; 8];
    b[..size].copy_from_slice(&bytes[at..at + size]);
    // Native byte order: C reads these fields as integers of this machine.
    if cfg!(target_endian = "little") {
        u64::from_le_bytes(b)
    } else {
        u64::from_be_bytes(b) >> (8 * (8 - size))
    }
}

fn write(bytes: &mut [u8], at: usize, size: usize, v: u64) {
    let b = if cfg!(target_endian = "little") {
        v.to_le_bytes()
    } else {
        (v << (8 * (8 - size))).to_be_bytes()
    };
    bytes[at..at + size].copy_from_slice(&b[..size]);
}

macro_rules! mirror {
    ($(#[$doc:meta])* $c:ident, $align:literal, $layout:ident, $list:path, $n:ident) => {
        $(#[$doc])*
        #[repr(C, align($align))]
        #[derive(Clone, Copy, PartialEq, Eq)]
        pub struct $c {
            bytes: [u8; $layout.total],
        }

        impl Default for $c {
            fn default() -> Self {
                $c { bytes: [0; $layout.total] }
            }
        }

        impl $c {
            /// Number of fields.
            pub const LEN: usize = $n;

            /// Field `k` (table order), `None` out of range.
            pub fn get(&self, k: usize) -> Option<u64> {
                (k < $n).then(|| read(&self.bytes, $layout.offset[k], $layout.size[k]))
            }

            /// Write field `k` (the value is truncated to the field's C type); false out of range.
            pub fn set(&mut self, k: usize, v: u64) -> bool {
                if k >= $n {
                    return false;
                }
                write(&mut self.bytes, $layout.offset[k], $layout.size[k], v);
                true
            }

            /// Every field, in table order.
            pub fn values(&self) -> [u64; $n] {
                std::array::from_fn(|k| read(&self.bytes, $layout.offset[k], $layout.size[k]))
            }
        }

        impl fmt::Debug for $c {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                let mut d = f.debug_struct(stringify!($c));
                for (s, v) in $list.iter().zip(self.values()) {
                    d.field(s.name, &v);
                }
                d.finish()
            }
        }
    };
}

mirror!(
    /// Top-level inputs of one clock cycle (`pmu50_inputs` of the header).
    pmu50_inputs, 2, INPUT_LAYOUT, signals::INPUTS, N_INPUTS
);
mirror!(
    /// Top-level outputs, in vector-column order (`pmu50_outputs` of the header).
    pmu50_outputs, 2, OUTPUT_LAYOUT, signals::OUTPUTS, N_OUTPUTS
);
mirror!(
    /// Combinational internals of the cycle that ends at an edge (`pmu50_internals`).
    pmu50_internals, 1, INTERNAL_LAYOUT, signals::INTERNALS, N_INTERNALS
);

impl From<pmu50_inputs> for Inputs {
    /// Any non-zero 1-bit input is true.
    fn from(c: pmu50_inputs) -> Self {
        let mut i = Inputs::default();
        for (set, v) in signals::INPUT_SETTERS.iter().zip(c.values()) {
            set(&mut i, v);
        }
        i
    }
}

impl From<Inputs> for pmu50_inputs {
    fn from(i: Inputs) -> Self {
        let mut c = pmu50_inputs::default();
        for (k, s) in signals::INPUTS.iter().enumerate() {
            c.set(k, (s.get)(&i));
        }
        c
    }
}

impl From<Outputs> for pmu50_outputs {
    fn from(o: Outputs) -> Self {
        let mut c = pmu50_outputs::default();
        for (k, s) in signals::OUTPUTS.iter().enumerate() {
            c.set(k, (s.get)(&o));
        }
        c
    }
}

impl From<Internals> for pmu50_internals {
    fn from(x: Internals) -> Self {
        let mut c = pmu50_internals::default();
        for (k, s) in signals::INTERNALS.iter().enumerate() {
            c.set(k, (s.get)(&x));
        }
        c
    }
}

fn c_struct<T, const N: usize>(
    out: &mut String,
    doc: &str,
    name: &str,
    list: &[Signal<T>],
    l: &Layout<N>,
) {
    *out += doc;
    *out += &format!("typedef struct {name} {{\n");
    for (s, &sz) in list.iter().zip(&l.size) {
        let field = format!("    {:<8} {};", c_type(sz), s.name);
        *out += &format!("{field:<28} /* [{}] {} */\n", s.width.doc(), s.meaning);
    }
    *out += &format!("}} {name};\n");
}

/// The generated part of `include/pmu50.h`: counts, the three structs, the register index list.
pub fn c_structs() -> String {
    let mut h = String::new();
    h += &format!("#define PMU50_INPUT_COUNT    {N_INPUTS}\n");
    h += &format!("#define PMU50_OUTPUT_COUNT   {N_OUTPUTS}\n");
    h += &format!("#define PMU50_REG_COUNT      {N_REGISTERS}\n");
    h += &format!("#define PMU50_INTERNAL_COUNT {N_INTERNALS}\n\n");
    c_struct(
        &mut h,
        "/* Inputs of one clock cycle (held during the cycle, sampled at the rising edge). */\n",
        "pmu50_inputs",
        signals::INPUTS,
        &INPUT_LAYOUT,
    );
    c_struct(
        &mut h,
        "\n/* Top-level outputs, in the order of docs/signals.md and of the vector file columns. A\n * field wider than its signal holds it in the low bits (upper bits 0). */\n",
        "pmu50_outputs",
        signals::OUTPUTS,
        &OUTPUT_LAYOUT,
    );
    c_struct(
        &mut h,
        "\n/* Combinational internals of the cycle that ends at an edge (model VCD scope pmu50.internals,\n * twin scope pmu50.internals). fig17 / fig18: path codes of spec 2.6. */\n",
        "pmu50_internals",
        signals::INTERNALS,
        &INTERNAL_LAYOUT,
    );
    h += "\n/* Registers by index (pmu50_reg_info, pmu50_reg_get, the rtl_regs array of pmu50_check):\n";
    for (k, r) in signals::REGISTERS.iter().enumerate() {
        h += &format!(" * {k:>3}  {:<38} {}\n", r.path(), r.width.doc());
    }
    h += " */\n";
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rust_layout_is_the_computed_c_layout() {
        assert_eq!(std::mem::size_of::<pmu50_inputs>(), INPUT_LAYOUT.total);
        assert_eq!(std::mem::size_of::<pmu50_outputs>(), OUTPUT_LAYOUT.total);
        assert_eq!(
            std::mem::size_of::<pmu50_internals>(),
            INTERNAL_LAYOUT.total
        );
        assert_eq!(std::mem::align_of::<pmu50_outputs>(), OUTPUT_LAYOUT.align);
        assert_eq!(
            std::mem::align_of::<pmu50_internals>(),
            INTERNAL_LAYOUT.align
        );
    }

    #[test]
    fn c_layout_rules() {
        // uint8_t a; uint16_t b; uint8_t c; -> offsets 0, 2, 4; size 6.
        let l: Layout<3> = {
            use pmu50_core::signals::{Dir, Radix, Reset, Width};
            const fn s(w: u8) -> Signal<u8> {
                Signal {
                    name: "x",
                    scope: "",
                    dir: Dir::In,
                    width: Width::Bits(w),
                    radix: Radix::Hex,
                    signed: false,
                    reset: Reset::None,
                    free_running: false,
                    contract: false,
                    meaning: "",
                    patent: "",
                    get: |_| 0,
                }
            }
            const L: &[Signal<u8>] = &[s(1), s(16), s(8)];
            layout(L)
        };
        assert_eq!((l.offset, l.total, l.align), ([0, 2, 4], 6, 2));
    }

    #[test]
    fn fields_round_trip_and_do_not_overlap() {
        let mut o = pmu50_outputs::default();
        for k in 0..N_OUTPUTS {
            assert!(o.set(k, k as u64 + 1));
        }
        for k in 0..N_OUTPUTS {
            assert_eq!(o.get(k), Some(k as u64 + 1));
        }
        assert_eq!(o.get(N_OUTPUTS), None);
        assert!(!o.set(N_OUTPUTS, 0));
    }

    #[test]
    fn inputs_convert_both_ways() {
        let i = Inputs {
            ig: true,
            cmp_c: true,
            bus_addr: 0x14,
            bus_wdata: 0xBEEF,
            ..Default::default()
        };
        let c: pmu50_inputs = i.into();
        assert_eq!(Inputs::from(c), i);
        let mut c = pmu50_inputs::default();
        c.set(0, 7); // any non-zero is true
        assert!(Inputs::from(c).ig);
    }
}
