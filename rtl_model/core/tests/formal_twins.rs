//! Twins of the formal property kit (hdl/formal/pmu50_formal.sv): every property of the kit is
//! stated here once more on the model, under the same name, and checked on random stimuli
//! (random legal parameters, key on/off runs, Vs2 good/bad, comparator changes, bus writes of
//! plausible and illegal values, W1C) against `Pmu50Spec`. The shadow below rebuilds from the
//! ports what the kit's shadow rebuilds (key pipeline, register file, timer, vld), so a rule
//! reads the same in both. `twin_names_match_the_kit` parses the .sv file: a property without a
//! twin (or a twin without a property) fails it.
// The rules keep the kit's form `!antecedent || consequent`, so that each reads like its assertion.
#![allow(clippy::nonminimal_bool)]

mod common;

use common::Rng;
use pmu50_core::{Inputs, Outputs, Params, Pmu50Spec};
use proptest::prelude::*;

/// Shadow state of the kit (`f_*` registers of pmu50_formal.sv), rebuilt from the ports.
#[derive(Clone, Copy, Debug)]
struct Sh {
    pipe: u8,
    /// The parameter registers `f_pw` ... `f_smp_on`.
    regs: common::RefParams,
    sig_q: bool,
    base: u16,
    vld: bool,
    wr_v: bool,
    wr_addr: u8,
    wr_data: u16,
}

/// The kit's combinational wires of one cycle.
#[derive(Clone, Copy, Debug, Default)]
struct W {
    tmr: u16,
    wt: u32,
    ps_start: u32,
    upd: bool,
    first: bool,
    chg_s: bool,
    chg_c: bool,
    pulse: bool,
    adp: bool,
    det: bool,
    short: u16,
    long: u16,
    inc: u8,
    expand: bool,
    count: bool,
    is_param: bool,
    legal: bool,
    param_wr: bool,
    refused: bool,
    skip_clr: bool,
    err_clr: bool,
    rd: u16,
    rd_fixed: bool,
    rd_cnt: bool,
}

fn reset_shadow(p: &Params) -> Sh {
    Sh {
        pipe: 0,
        regs: common::RefParams::new(p),
        sig_q: false,
        base: 0,
        vld: false,
        wr_v: false,
        wr_addr: 0,
        wr_data: 0,
    }
}

fn sext(v: u16, w: u8) -> u16 {
    common::signed(v, w) as u16
}

fn wires(s: &Sh, o: &Outputs, i: &Inputs, p: &Params) -> W {
    let mut w = W {
        tmr: if o.sig != s.sig_q { 0 } else { s.base },
        ..Default::default()
    };
    w.ps_start = u32::from(s.regs.pw) + u32::from(s.regs.pi);
    w.wt = w.ps_start + u32::from(s.regs.ps);
    w.upd = o.smp && o.sr;
    w.first = w.upd && !s.vld;
    w.chg_s = w.upd && s.vld && i.cmp_s != o.cs;
    w.chg_c = w.upd && s.vld && i.cmp_c != o.cc;
    w.pulse = o.smp && !o.sig;
    w.adp = w.pulse && s.regs.adaptive && o.sr;
    w.det = if w.chg_s {
        !o.hist_s
    } else {
        w.chg_c && !o.hist_c
    };
    w.short = o.si.saturating_sub(s.regs.t1).max(s.regs.si_min);
    w.long = (u32::from(o.si) + u32::from(s.regs.t2)).min(u32::from(s.regs.si_max)) as u16;
    w.inc = o.cnt_r.saturating_add(1);
    w.expand = w.adp && !w.det && o.si < s.regs.si_max && u16::from(o.cnt_r) >= s.regs.cth;
    w.count = w.adp && !w.det && o.si < s.regs.si_max && u16::from(o.cnt_r) < s.regs.cth;
    let a = i.bus_addr;
    let status_w = i.bus_we && o.sig && a == 0x14;
    w.is_param = (0x02..=0x0B).contains(&a);
    let d = i.bus_wdata;
    w.legal = s.regs.with_write(a, d).unwrap_or(s.regs).legal();
    w.param_wr = i.bus_we && o.sig && w.is_param && w.legal;
    w.refused = i.bus_we && !status_w && !w.param_wr;
    w.skip_clr = status_w && d & (1 << 5) != 0;
    w.err_clr = status_w && d & (1 << 9) != 0;
    let cw = p.cnt_width;
    w.rd = s.regs.read(a).unwrap_or(match a {
        0x00 => 0x5050,
        0x01 => 0x0001,
        0x0C => (u16::from(cw) << 8) | u16::from(p.sync_depth),
        0x10 => sext(o.cnt_s, cw),
        0x11 => sext(o.cnt_c, cw),
        0x12 => u16::from(o.cnt_r),
        0x13 => o.si,
        0x14 => [
            o.cs,
            o.cc,
            o.hist_s,
            o.hist_c,
            o.diag,
            o.quadrant_skip,
            o.sig,
            s.vld,
            o.sr,
            o.bus_err,
        ]
        .iter()
        .enumerate()
        .fold(0, |acc, (k, &b)| acc | (u16::from(b) << k)),
        _ => 0,
    });
    w.rd_fixed = a <= 0x01 || a == 0x0C || (a > 0x0C && a < 0x10) || a > 0x14;
    w.rd_cnt = (0x10..=0x13).contains(&a);
    w
}

fn next_shadow(s: &Sh, o: &Outputs, i: &Inputs, w: &W, p: &Params) -> Sh {
    let mut n = *s;
    let mask = (1u16 << p.sync_depth) - 1;
    n.pipe = (((u16::from(s.pipe) << 1) | u16::from(i.ig)) & mask) as u8;
    if w.param_wr {
        n.regs = s
            .regs
            .with_write(i.bus_addr, i.bus_wdata)
            .expect("a parameter write");
    }
    n.sig_q = o.sig;
    let period = if o.sig { s.regs.smp_on } else { o.si };
    let tinc = u32::from(w.tmr) + 1;
    n.base = if tinc >= u32::from(period) {
        0
    } else {
        tinc as u16
    };
    n.vld = s.vld || w.upd;
    n.wr_v = w.param_wr;
    n.wr_addr = i.bus_addr;
    n.wr_data = match i.bus_addr {
        0x02 => i.bus_wdata & 1,
        0x0A => i.bus_wdata & 0xFF,
        _ => i.bus_wdata,
    };
    n
}

/// One cycle of the trace as the kit sees it: this cycle (`out`, `shadow`, `wires`) and,
/// from the second cycle out of reset on (`live`), the cycle before (`po`, `pi`, `ps`, `pw`).
struct Cyc {
    after_reset: bool,
    live: bool,
    params: Params,
    out: Outputs,
    shadow: Sh,
    wires: W,
    po: Outputs,
    pi: Inputs,
    pw: W,
    prev_shadow: Option<Sh>,
    koff: bool,
}

impl Cyc {
    fn ones(&self) -> u16 {
        ((1u32 << self.params.cnt_width) - 1) as u16
    }
    fn add(&self, a: u16, b: i32) -> u16 {
        (i32::from(a) + b).rem_euclid(1 << self.params.cnt_width) as u16
    }
    fn held_56b(&self) -> bool {
        self.out.si == self.po.si
            && self.out.hist_s == self.po.hist_s
            && self.out.hist_c == self.po.hist_c
            && self.out.cnt_r == self.po.cnt_r
    }
}

/// Stimulus with memory: key runs, Vs2 mostly good, comparators held for a while, bus writes.
fn stimulus(
    rng: &mut Rng,
    o: &Outputs,
    s: &Sh,
    ig: &mut bool,
    run: &mut u64,
    cmp: &mut (bool, bool),
) -> Inputs {
    if *run == 0 {
        *ig = !*ig;
        *run = rng.range(1, 300);
    }
    *run -= 1;
    if rng.chance(1, 4) {
        *cmp = (rng.bit(), rng.bit());
    }
    let mut i = Inputs {
        ig: *ig,
        vs2_ok: !rng.chance(1, 20),
        cmp_s: cmp.0,
        cmp_c: cmp.1,
        ..Default::default()
    };
    i.bus_addr = rng.range(0, 0x18) as u8;
    if rng.chance(1, 12) {
        i.bus_we = true;
        i.bus_wdata = match rng.range(0, 4) {
            0 => rng.next() as u16,
            1 => rng.range(0, 12) as u16,
            2 => {
                (u32::from(s.regs.pw) + u32::from(s.regs.pi) + u32::from(s.regs.ps))
                    .saturating_sub(1) as u16
                    + rng.range(0, 3) as u16
            }
            3 => {
                if rng.bit() {
                    0x20
                } else {
                    0x200
                }
            }
            _ => o.si.wrapping_add(rng.range(0, 40) as u16),
        };
    }
    i
}

/// Runs `ticks` random cycles from reset and checks `rule` at every cycle.
fn check_rule(
    p: Params,
    seed: u64,
    ticks: usize,
    name: &str,
    rule: &dyn Fn(&Cyc) -> bool,
) -> Result<(), TestCaseError> {
    let mut m = Pmu50Spec::new(p).expect("legal parameters");
    let mut rng = Rng(seed);
    let (mut ig, mut run, mut cmp) = (false, rng.range(1, 40), (false, false));
    let mut s = reset_shadow(&p);
    let mut o = m.peek();
    let mut prev: Option<(Outputs, Inputs, W, Sh)> = None;
    for t in 0..ticks {
        let i = stimulus(&mut rng, &o, &s, &mut ig, &mut run, &mut cmp);
        let w = wires(&s, &o, &i, &p);
        let (po, pi, pw, psh) = prev.unwrap_or((o, i, w, s));
        let c = Cyc {
            after_reset: t == 0,
            live: t > 0,
            params: p,
            out: o,
            shadow: s,
            wires: w,
            po,
            pi,
            pw,
            prev_shadow: Some(psh),
            koff: t > 0 && po.sig && !o.sig,
        };
        prop_assert!(
            rule(&c),
            "{} fails at tick {} (parameters {:?}, seed {})",
            name,
            t,
            p,
            seed
        );
        prev = Some((o, i, w, s));
        s = next_shadow(&s, &o, &i, &w, &p);
        o = m.step(&i);
    }
    Ok(())
}

macro_rules! twins {
    ($($name:ident => $rule:expr;)*) => {
        const TWIN_NAMES: &[&str] = &[$(stringify!($name)),*];
        $(
            proptest! {
                #![proptest_config(common::cases(24))]
                #[test]
                fn $name(p in common::params(30, 40), seed in any::<u64>()) {
                    let rule: &dyn Fn(&Cyc) -> bool = &$rule;
                    check_rule(p, seed, 3000, stringify!($name), rule)?;
                }
            }
        )*
    };
}

twins! {
    prop_reset_values => |c: &Cyc| !c.after_reset || {
        let o = &c.out;
        !o.sig && !o.sr && !o.cs && !o.cc && o.cnt_s == 0 && o.cnt_c == 0 && o.cnt_r == 0 && o.si == c.params.si_max
            && !o.hist_s && !o.hist_c && !o.diag && !o.quadrant_skip && o.bus_rdata == 0 && !o.bus_err
    };
    prop_reset_window => |c: &Cyc| !c.after_reset || (c.out.st && c.out.vs2_en && !c.out.smp);
    prop_sig_sync => |c: &Cyc| c.out.sig == (c.shadow.pipe >> (c.params.sync_depth - 1) & 1 == 1);
    prop_rails_follow_sig => |c: &Cyc| {
        let o = &c.out;
        o.vr_hi == o.sig && o.vm_en == o.sig && o.vs1_en == o.sig && o.rail_hi == o.sig && o.vp_en
    };
    prop_st_pulse => |c: &Cyc| c.out.st == (!c.out.sig && c.wires.tmr == 0);
    prop_vs2_en_window => |c: &Cyc| c.out.vs2_en == (c.out.sig || u32::from(c.wires.tmr) < c.wires.wt);
    prop_ps_window => |c: &Cyc| c.out.ps_win == (!c.out.sig && u32::from(c.wires.tmr) >= c.wires.ps_start && u32::from(c.wires.tmr) < c.wires.wt);
    prop_smp_key_off => |c: &Cyc| c.out.sig || c.out.smp == (u32::from(c.wires.tmr) + 1 == c.wires.wt);
    prop_smp_key_on => |c: &Cyc| !c.out.sig || c.out.smp == (u32::from(c.wires.tmr) + 1 == u32::from(c.shadow.regs.smp_on));
    prop_diag => |c: &Cyc| {
        let d = c.add(c.out.cnt_s, -i32::from(c.out.cnt_c));
        c.out.diag == (!(d == 0 || d == 1 || d == c.ones()) || c.out.quadrant_skip)
    };
    prop_key_off_starts_output => |c: &Cyc| !c.koff || c.out.st;
    prop_sr_power_good => |c: &Cyc| !c.live || c.out.sr == (c.po.vs2_en && c.pi.vs2_ok);
    prop_latch_hold => |c: &Cyc| !c.live || c.pw.upd || (c.out.cs == c.po.cs && c.out.cc == c.po.cc);
    prop_latch_sample => |c: &Cyc| !c.live || !c.pw.upd || (c.out.cs == c.pi.cmp_s && c.out.cc == c.pi.cmp_c);
    prop_first_preset => |c: &Cyc| !c.live || !c.pw.first || matches!(
        (c.out.cs, c.out.cc, c.out.cnt_s, c.out.cnt_c), (true, true, 0, 0) | (true, false, 0, 1) | (false, false, 1, 1) | (false, true, 1, 2));
    prop_cnt_s_0096 => |c: &Cyc| !c.live || !(c.pw.chg_s && !c.pw.chg_c && c.po.cc)
        || (c.out.cnt_s == c.add(c.po.cnt_s, if c.out.cs { 1 } else { -1 }) && c.out.cnt_c == c.po.cnt_c);
    prop_cnt_s_0097 => |c: &Cyc| !c.live || !(c.pw.chg_s && !c.pw.chg_c && !c.po.cc)
        || (c.out.cnt_s == c.add(c.po.cnt_s, if c.out.cs { -1 } else { 1 }) && c.out.cnt_c == c.po.cnt_c);
    prop_cnt_c_0098 => |c: &Cyc| !c.live || !(c.pw.chg_c && !c.pw.chg_s && !c.po.cs)
        || (c.out.cnt_c == c.add(c.po.cnt_c, if c.out.cc { 1 } else { -1 }) && c.out.cnt_s == c.po.cnt_s);
    prop_cnt_c_0099 => |c: &Cyc| !c.live || !(c.pw.chg_c && !c.pw.chg_s && c.po.cs)
        || (c.out.cnt_c == c.add(c.po.cnt_c, if c.out.cc { -1 } else { 1 }) && c.out.cnt_s == c.po.cnt_s);
    prop_cnt_wrap => |c: &Cyc| {
        let step = |a: u16, b: u16| { let d = c.add(a, -i32::from(b)); d == 1 || d == c.ones() };
        !c.live || !(c.pw.chg_s ^ c.pw.chg_c) || c.pw.first
            || (step(c.out.cnt_s, c.po.cnt_s) != step(c.out.cnt_c, c.po.cnt_c))
    };
    prop_cnt_hold => |c: &Cyc| !c.live || c.pw.first || (c.pw.chg_s ^ c.pw.chg_c)
        || (c.out.cnt_s == c.po.cnt_s && c.out.cnt_c == c.po.cnt_c);
    prop_quadrant_skip => |c: &Cyc| !c.live
        || c.out.quadrant_skip == ((c.pw.chg_s && c.pw.chg_c) || (c.po.quadrant_skip && !c.pw.skip_clr));
    prop_si_moves_at_pulse => |c: &Cyc| !c.live || c.out.si == c.po.si || c.koff || c.pw.pulse;
    prop_key_on_holds => |c: &Cyc| !c.live || !(c.out.sig && c.po.sig) || c.held_56b();
    prop_koff_reload => |c: &Cyc| !c.koff || (c.out.si == c.shadow.regs.si_max && !c.out.hist_s && !c.out.hist_c && c.out.cnt_r == 0);
    prop_fixed_interval => |c: &Cyc| !c.live || !(c.pw.pulse && !c.ps_adaptive()) || (c.out.si == c.ps_si_max()
        && c.out.hist_s == c.po.hist_s && c.out.hist_c == c.po.hist_c && c.out.cnt_r == c.po.cnt_r);
    prop_s1_no_rise => |c: &Cyc| !c.live || !(c.pw.pulse && c.ps_adaptive() && !c.po.sr) || c.held_56b();
    prop_si_shorten => |c: &Cyc| !c.live || !(c.pw.adp && c.pw.det)
        || (c.out.cnt_r == 0 && c.out.si == if c.po.si <= c.ps_si_min() { c.po.si } else { c.pw.short });
    prop_si_hold_at_max => |c: &Cyc| !c.live || !(c.pw.adp && !c.pw.det && c.po.si >= c.ps_si_max())
        || (c.out.si == c.po.si && c.out.cnt_r == c.po.cnt_r);
    prop_si_expand => |c: &Cyc| !c.live || !c.pw.expand || (c.out.si == c.pw.long && c.out.cnt_r == c.pw.inc);
    prop_s11_clear => |c: &Cyc| !c.live || !c.pw.expand || (!c.out.hist_s && !c.out.hist_c);
    prop_cnt_r_count => |c: &Cyc| !c.live || !c.pw.count || (c.out.cnt_r == c.po.cnt_r + 1 && c.out.si == c.po.si
        && c.out.hist_s == c.po.hist_s && c.out.hist_c == c.po.hist_c);
    prop_cnt_r_saturates => |c: &Cyc| !c.live || c.out.cnt_r == c.po.cnt_r || c.out.cnt_r == 0
        || (c.po.cnt_r != 255 && c.out.cnt_r == c.po.cnt_r + 1);
    prop_hist_detect => |c: &Cyc| !c.live || !(c.pw.adp && c.pw.det)
        || ((c.out.hist_s, c.out.hist_c) == if c.pw.chg_s { (true, false) } else { (false, true) });
    prop_hist_moves => |c: &Cyc| !c.live || (c.out.hist_s == c.po.hist_s && c.out.hist_c == c.po.hist_c) || c.koff || c.pw.adp;
    prop_read_fixed => |c: &Cyc| !c.live || !c.pw.rd_fixed || c.out.bus_rdata == c.pw.rd;
    prop_read_params => |c: &Cyc| !c.live || !c.pw.is_param || c.out.bus_rdata == c.pw.rd;
    prop_read_counters => |c: &Cyc| !c.live || !c.pw.rd_cnt || c.out.bus_rdata == c.pw.rd;
    prop_read_status => |c: &Cyc| !c.live || c.pi.bus_addr != 0x14 || c.out.bus_rdata == c.pw.rd;
    prop_write_key_off_refused => |c: &Cyc| !c.live || !(c.pi.bus_we && !c.po.sig) || c.out.bus_err;
    prop_write_illegal_refused => |c: &Cyc| !c.live || !(c.pi.bus_we && c.po.sig && c.pw.is_param && !c.pw.legal) || c.out.bus_err;
    prop_write_ro_refused => |c: &Cyc| !c.live || !(c.pi.bus_we && c.po.sig && !c.pw.is_param && c.pi.bus_addr != 0x14) || c.out.bus_err;
    prop_write_accepted => |c: &Cyc| !c.live || ((!c.pw.param_wr || c.out.bus_err == c.po.bus_err)
        && (!(c.ps_wr_v() && c.pi.bus_addr == c.ps_wr_addr()) || c.out.bus_rdata == c.ps_wr_data()));
    prop_bus_err_w1c => |c: &Cyc| !c.live || c.out.bus_err == (c.pw.refused || (c.po.bus_err && !c.pw.err_clr));
}

/// The shadow of the cycle before, for the rules that use `$past(f_...)` registers.
impl Cyc {
    fn ps_adaptive(&self) -> bool {
        self.pshadow().regs.adaptive
    }
    fn ps_si_max(&self) -> u16 {
        self.pshadow().regs.si_max
    }
    fn ps_si_min(&self) -> u16 {
        self.pshadow().regs.si_min
    }
    fn ps_wr_v(&self) -> bool {
        self.pshadow().wr_v
    }
    fn ps_wr_addr(&self) -> u8 {
        self.pshadow().wr_addr
    }
    fn ps_wr_data(&self) -> u16 {
        self.pshadow().wr_data
    }
    fn pshadow(&self) -> Sh {
        self.prev_shadow.expect("a cycle before")
    }
}

#[test]
fn twin_names_match_the_kit() {
    let sv = include_str!("../../../hdl/formal/pmu50_formal.sv");
    let mut kit: Vec<&str> = sv
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("// @prop "))
        .filter_map(|l| l.split('|').next())
        .map(str::trim)
        .filter(|n| n.starts_with("prop_"))
        .collect();
    let mut twins: Vec<&str> = TWIN_NAMES.to_vec();
    assert!(kit.len() >= 25, "the kit states {} properties", kit.len());
    kit.sort_unstable();
    twins.sort_unstable();
    assert_eq!(
        kit, twins,
        "properties of hdl/formal/pmu50_formal.sv and their twins differ"
    );
}
