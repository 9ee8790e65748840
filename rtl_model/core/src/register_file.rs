//! Register file: the microprocessor's view of the PMU 50 digital core.
//!
//! Paragraphs: [0108]/[0163] (at key-on the MPU reads CNTs and CNTc), [0321]-[0323] (Pw, Pi, Ps
//! programmable), [0259] (T1, T2, x, minimum, Cth set according to the device), [0349] (on-key
//! sampling period).
//!
//! Bus: one write port and one registered read port, 8-bit address, 16-bit data. A write is
//! accepted at the edge where `bus_we` = 1; `bus_rdata` shows, one cycle later, the register at
//! the address presented in the previous cycle. The MPU is powered only while the key is on
//! ([0205]), so writes while `sig` = 0 are refused.
//!
//! A write is refused (register unchanged, sticky `bus_err` set) when the address is not writable,
//! when `sig` = 0, or when the new value would make the parameter set illegal (the rules of
//! [`crate::params::Params::validate`]: no zero period, minimum <= x, Wt < shortest interval). The
//! parameter registers therefore always hold a legal set. When raising both x and the minimum,
//! write x first; when lowering both, write the minimum first.
//!
//! Register map (also in docs/spec.md):
//!
//! | addr | name     | width | access | reset | content |
//! |------|----------|-------|--------|-------|---------|
//! | 0x00 | ID       | 16 | RO  | 0x5050 | identifies PMU 50 |
//! | 0x01 | VERSION  | 16 | RO  | 0x0001 | register map version |
//! | 0x02 | CTRL     | 1  | RW  | adaptive | bit 0 adaptive drive interval |
//! | 0x03 | PW       | 16 | RW  | 5      | waiting period Pw, ticks |
//! | 0x04 | PI       | 16 | RW  | 12     | idle period Pi, ticks |
//! | 0x05 | PS       | 16 | RW  | 5      | sampling period Ps, ticks |
//! | 0x06 | SI_MAX   | 16 | RW  | 660    | maximum interval x, ticks |
//! | 0x07 | SI_MIN   | 16 | RW  | 220    | minimum interval, ticks |
//! | 0x08 | T1       | 16 | RW  | 220    | shortening step, ticks |
//! | 0x09 | T2       | 16 | RW  | 110    | expanding step, ticks |
//! | 0x0A | CTH      | 8  | RW  | 4      | count threshold Cth |
//! | 0x0B | SMP_ON   | 16 | RW  | 10     | on-key sampling period, ticks |
//! | 0x0C | CFG      | 16 | RO  | -      | [2:0] sync_depth, [12:8] cnt_width |
//! | 0x10 | CNT_S    | 16 | RO  | 0      | CNTs sign-extended to 16 bits |
//! | 0x11 | CNT_C    | 16 | RO  | 0      | CNTc sign-extended to 16 bits |
//! | 0x12 | CNT_R    | 8  | RO  | 0      | power supply count CNTr |
//! | 0x13 | SI       | 16 | RO  | x      | current drive interval, ticks |
//! | 0x14 | STATUS   | 10 | RO/W1C | 0   | see [`status`] |
//!
//! Ports ([`RegisterFile::outputs`]: registered; [`RegisterFile::eval`]: next state and the
//! combinational `skip_clr`). Structural parameters `sync_depth`, `cnt_width` are fixed when the
//! block is built ([`RegisterFile::new`]).
//!
//! | port      | width | dir | meaning |
//! |-----------|-------|-----|---------|
//! | `bus_we`, `bus_addr`, `bus_wdata` | 1, 8, 16 | in | write strobe, address, data |
//! | `sig`     | 1     | in  | key on: writes are accepted only then |
//! | `view`    | -     | in  | registers of the other blocks, for the read mux ([`StatusView`]) |
//! | `params`  | -     | out | the parameter registers in force ([`Params`], registered) |
//! | `bus_rdata` | 16  | out | registered read data |
//! | `bus_err` | 1     | out | sticky refused write (registered) |
//! | `skip_clr`| 1     | out | W1C strobe of STATUS.quadrant_skip (combinational) |
//!
//! Reset values of the RW registers are the configured parameters (the patent's defaults unless a
//! scenario overrides them); unknown addresses read 0.
//!
//! | register  | width | reset | meaning |
//! |-----------|-------|-------|---------|
//! | `adaptive`| 1     | cfg   | CTRL bit 0 |
//! | `pw`, `pi`, `ps`, `si_max`, `si_min`, `t1`, `t2`, `smp_on` | 16 | cfg | periods in ticks |
//! | `cth`     | 8     | cfg   | Cth |
//! | `bus_err` | 1     | 0     | sticky: a write was refused |
//! | `rdata`   | 16    | 0     | registered read data |

use crate::params::{ParamValue, Params};
use bitvec::prelude::*;

pub mod addr {
    pub const ID: u8 = 0x00;
    pub const VERSION: u8 = 0x01;
    pub const CTRL: u8 = 0x02;
    pub const PW: u8 = 0x03;
    pub const PI: u8 = 0x04;
    pub const PS: u8 = 0x05;
    pub const SI_MAX: u8 = 0x06;
    pub const SI_MIN: u8 = 0x07;
    pub const T1: u8 = 0x08;
    pub const T2: u8 = 0x09;
    pub const CTH: u8 = 0x0A;
    pub const SMP_ON: u8 = 0x0B;
    pub const CFG: u8 = 0x0C;
    pub const CNT_S: u8 = 0x10;
    pub const CNT_C: u8 = 0x11;
    pub const CNT_R: u8 = 0x12;
    pub const SI: u8 = 0x13;
    pub const STATUS: u8 = 0x14;
}

/// Bit positions of STATUS (0x14).
pub mod status {
    pub const CS: usize = 0;
    pub const CC: usize = 1;
    pub const HIST_S: usize = 2;
    pub const HIST_C: usize = 3;
    pub const DIAG: usize = 4;
    /// W1C.
    pub const QUADRANT_SKIP: usize = 5;
    pub const SIG: usize = 6;
    pub const VLD: usize = 7;
    pub const SR: usize = 8;
    /// W1C.
    pub const BUS_ERR: usize = 9;
}

pub const ID_VALUE: u16 = 0x5050;
pub const VERSION_VALUE: u16 = 0x0001;

/// Name, address, width and access of every register, for docs, the CLI and the HDL kit.
pub const MAP: &[(&str, u8, u8, &str)] = &[
    ("ID", addr::ID, 16, "RO"),
    ("VERSION", addr::VERSION, 16, "RO"),
    ("CTRL", addr::CTRL, 1, "RW"),
    ("PW", addr::PW, 16, "RW"),
    ("PI", addr::PI, 16, "RW"),
    ("PS", addr::PS, 16, "RW"),
    ("SI_MAX", addr::SI_MAX, 16, "RW"),
    ("SI_MIN", addr::SI_MIN, 16, "RW"),
    ("T1", addr::T1, 16, "RW"),
    ("T2", addr::T2, 16, "RW"),
    ("CTH", addr::CTH, 8, "RW"),
    ("SMP_ON", addr::SMP_ON, 16, "RW"),
    ("CFG", addr::CFG, 16, "RO"),
    ("CNT_S", addr::CNT_S, 16, "RO"),
    ("CNT_C", addr::CNT_C, 16, "RO"),
    ("CNT_R", addr::CNT_R, 8, "RO"),
    ("SI", addr::SI, 16, "RO"),
    ("STATUS", addr::STATUS, 10, "RO/W1C"),
];

/// Look up a register address by name (case-insensitive).
pub fn address_of(name: &str) -> Option<u8> {
    MAP.iter()
        .find(|(n, ..)| n.eq_ignore_ascii_case(name))
        .map(|&(_, a, ..)| a)
}

macro_rules! parameter_registers {
    (structural: [$(($sf:ident, $st:ty, $sh:literal, $sd:literal, $sdoc:literal),)*],
     programmable: [$(($f:ident, $t:ty, $h:literal, $d:literal, $a:ident, $doc:literal),)*]) => {
        /// The registers of the block: one per programmable parameter (the table of
        /// [`crate::param_table!`]), the sticky `bus_err` and the registered read data.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub struct Regs {
            $(#[doc = $doc] pub $f: $t,)*
            /// Sticky: a write was refused.
            pub bus_err: bool,
            /// Registered read data.
            pub rdata: u16,
        }

        /// Reset with the configured parameter values.
        pub const fn reset(p: &Params) -> Regs {
            Regs { $($f: p.$f,)* bus_err: false, rdata: 0 }
        }

        impl Regs {
            pub fn params(&self, sync_depth: u8, cnt_width: u8) -> Params {
                Params { sync_depth, cnt_width, $($f: self.$f,)* }
            }

            /// The value of the parameter register at `a`, `None` when `a` is not one.
            fn read_parameter(&self, a: u8) -> Option<u16> {
                match a {
                    $(addr::$a => Some(ParamValue::to_bus(self.$f)),)*
                    _ => None,
                }
            }
        }

        /// The register set after a parameter write, or `None` when the address is not a
        /// parameter.
        pub fn with_write(r: &Regs, a: u8, d: u16) -> Option<Regs> {
            let mut n = *r;
            match a {
                $(addr::$a => n.$f = ParamValue::from_bus(d),)*
                _ => return None,
            }
            Some(n)
        }
    };
}

crate::param_table!(parameter_registers);

/// Reset with the patent's defaults; the top level uses [`reset`] with the configured values.
pub const RESET: Regs = reset(&Params::DEFAULT);

/// Read-only state of the other blocks, as seen by the read mux (register values before the edge).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct StatusView {
    pub cnt_s: u16,
    pub cnt_c: u16,
    pub cnt_r: u8,
    pub si: u16,
    pub cs: bool,
    pub cc: bool,
    pub hist_s: bool,
    pub hist_c: bool,
    pub diag: bool,
    pub quadrant_skip: bool,
    pub sig: bool,
    pub vld: bool,
    pub sr: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Inputs {
    pub bus_we: bool,
    pub bus_addr: u8,
    pub bus_wdata: u16,
    pub sig: bool,
    pub view: StatusView,
}

/// Registered outputs (functions of the registers only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Outputs {
    /// The parameter registers as used by the other blocks in this cycle.
    pub params: Params,
    pub bus_rdata: u16,
    pub bus_err: bool,
}

/// Combinational outputs of the cycle (they depend on the bus inputs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Comb {
    /// Write-1-to-clear strobe of STATUS.quadrant_skip.
    pub skip_clr: bool,
}

/// The block with its structural parameters (visible in CFG, used by the legality check of a
/// write and the sign extension of CNT_S/CNT_C), fixed at construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RegisterFile {
    sync_depth: u8,
    cnt_width: u8,
}

/// STATUS as a 16-bit word.
pub fn status_word(v: &StatusView, bus_err: bool) -> u16 {
    let mut w = bitarr![u16, Lsb0; 0; 16];
    w.set(status::CS, v.cs);
    w.set(status::CC, v.cc);
    w.set(status::HIST_S, v.hist_s);
    w.set(status::HIST_C, v.hist_c);
    w.set(status::DIAG, v.diag);
    w.set(status::QUADRANT_SKIP, v.quadrant_skip);
    w.set(status::SIG, v.sig);
    w.set(status::VLD, v.vld);
    w.set(status::SR, v.sr);
    w.set(status::BUS_ERR, bus_err);
    w.load_le::<u16>()
}

/// Why the chip refuses a bus write (sets `bus_err`, registers unchanged).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WriteRefusal {
    /// `sig` = 0: the MPU is not powered ([0205]).
    KeyOff,
    /// The address is not a writable register.
    NotWritable,
    /// The new value would make the parameter set illegal.
    Illegal(crate::params::ParamError),
}

impl RegisterFile {
    pub const fn new(sync_depth: u8, cnt_width: u8) -> Self {
        RegisterFile {
            sync_depth,
            cnt_width,
        }
    }

    /// The parameter set the registers hold, with this block's structural parameters.
    pub fn params(&self, r: &Regs) -> Params {
        r.params(self.sync_depth, self.cnt_width)
    }

    /// Registered outputs, decoded from the registers.
    pub fn outputs(&self, r: &Regs) -> Outputs {
        Outputs {
            params: self.params(r),
            bus_rdata: r.rdata,
            bus_err: r.bus_err,
        }
    }

    /// Combinational read mux.
    pub fn read(&self, r: &Regs, i: &Inputs, a: u8) -> u16 {
        let sx = |v: u16| crate::updown_counter_58cd::sext(v, self.cnt_width) as i16 as u16;
        if let Some(v) = r.read_parameter(a) {
            return v;
        }
        match a {
            addr::ID => ID_VALUE,
            addr::VERSION => VERSION_VALUE,
            addr::CFG => u16::from(self.sync_depth & 0x7) | (u16::from(self.cnt_width & 0x1F) << 8),
            addr::CNT_S => sx(i.view.cnt_s),
            addr::CNT_C => sx(i.view.cnt_c),
            addr::CNT_R => u16::from(i.view.cnt_r),
            addr::SI => i.view.si,
            addr::STATUS => status_word(&i.view, r.bus_err),
            _ => 0,
        }
    }

    /// The bus write of this cycle: `Ok(Some(regs))` a parameter write that is taken, `Ok(None)`
    /// no parameter write (no `bus_we`, or a STATUS write-1-to-clear), `Err` refused and why.
    pub fn bus_write(&self, r: &Regs, i: &Inputs) -> Result<Option<Regs>, WriteRefusal> {
        if !i.bus_we {
            return Ok(None);
        }
        if !i.sig {
            return Err(WriteRefusal::KeyOff);
        }
        if i.bus_addr == addr::STATUS {
            return Ok(None);
        }
        let cand = with_write(r, i.bus_addr, i.bus_wdata).ok_or(WriteRefusal::NotWritable)?;
        self.params(&cand)
            .validate()
            .map_err(WriteRefusal::Illegal)?;
        Ok(Some(cand))
    }

    /// Pure next-state function, with the combinational outputs of the cycle.
    pub fn eval(&self, r: &Regs, i: &Inputs) -> (Comb, Regs) {
        let status_w1c = i.bus_we && i.sig && i.bus_addr == addr::STATUS;
        let w1c = |bit: usize| status_w1c && (i.bus_wdata >> bit) & 1 == 1;
        let mut n = *r;
        let write = self.bus_write(r, i);
        if let Ok(Some(cand)) = write {
            n = cand;
        }
        let refused = write.is_err();
        // Set wins over clear.
        n.bus_err = refused || (r.bus_err && !w1c(status::BUS_ERR));
        n.rdata = self.read(r, i, i.bus_addr);
        (
            Comb {
                skip_clr: w1c(status::QUADRANT_SKIP),
            },
            n,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RF: RegisterFile = RegisterFile::new(2, 16);

    fn wr(r: &Regs, a: u8, d: u16, sig: bool) -> (Comb, Regs) {
        RF.eval(
            r,
            &Inputs {
                bus_we: true,
                bus_addr: a,
                bus_wdata: d,
                sig,
                ..Default::default()
            },
        )
    }

    /// (`t2`, `bus_err`) after a write of 220 to T2 from reset, with `sig` (key on) as given.
    fn t2_after_write(sig: bool) -> (u16, bool) {
        let (_, n) = wr(&RESET, addr::T2, 220, sig);
        (n.t2, n.bus_err)
    }

    #[test]
    fn legal_write_is_taken() {
        assert_eq!(t2_after_write(true), (220, false));
    }

    #[test]
    fn illegal_writes_are_refused_and_flagged() {
        for (a, d) in [
            (addr::SI_MIN, 0),   // zero
            (addr::SI_MIN, 700), // min above x
            (addr::SI_MAX, 100), // x below min
            (addr::PI, 300),     // Wt >= min
            (addr::CTH, 0),      // Cth zero
            (addr::CNT_S, 5),    // read-only
            (0x7F, 5),           // unmapped
        ] {
            let (_, n) = wr(&RESET, a, d, true);
            assert!(n.bus_err, "addr {a:#x} value {d}");
            assert_eq!(n.params(2, 16), RESET.params(2, 16));
        }
    }

    #[test]
    fn writes_while_key_off_are_refused() {
        assert_eq!(t2_after_write(false), (110, true));
    }

    #[test]
    fn status_w1c_clears_skip_and_bus_err() {
        let r = Regs {
            bus_err: true,
            ..RESET
        };
        let (o, n) = wr(
            &r,
            addr::STATUS,
            (1 << status::QUADRANT_SKIP) | (1 << status::BUS_ERR),
            true,
        );
        assert!(o.skip_clr && !n.bus_err);
        let (o, n) = wr(&r, addr::STATUS, 0, true);
        assert!(!o.skip_clr && n.bus_err);
    }

    #[test]
    fn read_is_registered_and_sign_extends_counts() {
        let view = StatusView {
            cnt_s: 0x7,
            cnt_c: 0x2,
            ..Default::default()
        };
        let i = Inputs {
            bus_addr: addr::CNT_S,
            view,
            ..Default::default()
        };
        let rf = RegisterFile::new(2, 3);
        let (_, n) = rf.eval(&RESET, &i);
        assert_eq!(
            rf.outputs(&RESET).bus_rdata,
            0,
            "data appears one cycle later"
        );
        assert_eq!(rf.outputs(&n).bus_rdata, 0xFFFF, "3-bit 0b111 is -1");
        assert_eq!(rf.read(&RESET, &i, addr::ID), ID_VALUE);
        assert_eq!(rf.read(&RESET, &i, addr::CFG), 0x0302);
    }

    #[test]
    fn status_bits_are_where_the_map_says() {
        let v = StatusView {
            cs: true,
            diag: true,
            sr: true,
            ..Default::default()
        };
        assert_eq!(status_word(&v, true), 0b10_0001_0001 | (1 << 8));
    }

    #[test]
    fn map_names_resolve() {
        assert_eq!(address_of("cnt_s"), Some(addr::CNT_S));
        assert_eq!(address_of("nope"), None);
    }
}
