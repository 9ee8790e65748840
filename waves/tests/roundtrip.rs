//! Property: whatever the writer writes reads back (through wellen) as exactly
//! the value changes a reference model predicts: full values at the first
//! written instant, afterwards only real changes, nothing outside the window.

use pmu50_waves::reader::{SignalKind, Value, Waveform};
use pmu50_waves::writer::{BitType, Logic, VcdBuilder, WriteError};
use pmu50_waves::{TimeUnit, Timescale};
use proptest::prelude::*;

#[derive(Debug, Clone)]
enum Decl {
    Bit(BitType),
    Vector(BitType, u32, u32),
    Real,
}

#[derive(Debug, Clone)]
enum Change {
    Bit(Logic),
    Int(u64),
    Bits(Vec<u8>),
    Real(f64),
}

fn logic() -> impl Strategy<Value = Logic> {
    prop_oneof![
        4 => Just(Logic::Zero),
        4 => Just(Logic::One),
        1 => Just(Logic::X),
        1 => Just(Logic::Z)
    ]
}

fn bit_type() -> impl Strategy<Value = BitType> {
    prop_oneof![Just(BitType::Wire), Just(BitType::Reg)]
}

fn decl() -> impl Strategy<Value = Decl> {
    prop_oneof![
        bit_type().prop_map(Decl::Bit),
        (bit_type(), 0u32..80, 0u32..80).prop_map(|(t, m, l)| Decl::Vector(t, m, l)),
        Just(Decl::Real),
    ]
}

fn width(d: &Decl) -> u32 {
    match d {
        Decl::Bit(_) => 1,
        Decl::Vector(_, m, l) => m.abs_diff(*l) + 1,
        Decl::Real => 64,
    }
}

fn real() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        Just(-0.0),
        Just(1.0),
        Just(3.3),
        Just(1e300),
        Just(-1e-300),
        Just(f64::MIN_POSITIVE),
        Just(5e-324), // subnormal
        Just(-123456789.125),
        Just(f64::MAX),
        (-1e6f64..1e6),
        any::<f64>().prop_filter("finite", |v| v.is_finite()),
    ]
}

fn change_for(d: &Decl) -> BoxedStrategy<Change> {
    let w = width(d);
    match d {
        Decl::Real => real().prop_map(Change::Real).boxed(),
        Decl::Bit(_) => logic().prop_map(Change::Bit).boxed(),
        Decl::Vector(..) => {
            let small = if w >= 64 {
                any::<u64>().boxed()
            } else {
                (0..(1u64 << w)).boxed()
            };
            // few distinct values so that "same value again" happens often
            let repeat =
                (0u64..3).prop_map(move |v| v.min(if w >= 64 { u64::MAX } else { (1 << w) - 1 }));
            prop_oneof![
                3 => small.prop_map(Change::Int),
                3 => repeat.prop_map(Change::Int),
                2 => proptest::collection::vec(logic(), w as usize)
                    .prop_map(|v| Change::Bits(v.into_iter().map(bit_char).collect())),
            ]
            .boxed()
        }
    }
}

fn bit_char(l: Logic) -> u8 {
    match l {
        Logic::Zero => b'0',
        Logic::One => b'1',
        Logic::X => b'x',
        Logic::Z => b'z',
    }
}

/// (declarations, steps: (time delta, changes (var index, change)), window)
type Case = (
    Vec<Decl>,
    Vec<(u64, Vec<(usize, Change)>)>,
    Option<(u64, u64)>,
);

fn case() -> impl Strategy<Value = Case> {
    proptest::collection::vec(decl(), 1..7).prop_flat_map(|decls| {
        let n = decls.len();
        let per_var: Vec<BoxedStrategy<Change>> = decls.iter().map(change_for).collect();
        let change = (0..n).prop_flat_map(move |i| per_var[i].clone().prop_map(move |c| (i, c)));
        let step = (0u64..4, proptest::collection::vec(change, 0..6));
        let window = proptest::option::of((0u64..40, 1u64..40).prop_map(|(s, len)| (s, s + len)));
        (Just(decls), proptest::collection::vec(step, 0..25), window)
    })
}

fn to_value(d: &Decl, c: &Change) -> Value {
    match c {
        Change::Bit(l) => Value::Bits((bit_char(*l) as char).to_string()),
        Change::Int(v) => {
            let w = width(d);
            Value::Bits(
                (0..w)
                    .rev()
                    .map(|i| {
                        if i < 64 && (v >> i) & 1 == 1 {
                            '1'
                        } else {
                            '0'
                        }
                    })
                    .collect(),
            )
        }
        Change::Bits(b) => Value::Bits(String::from_utf8(b.clone()).unwrap()),
        Change::Real(r) => Value::Real(*r + 0.0),
    }
}

fn initial(d: &Decl) -> Value {
    match d {
        Decl::Real => Value::Real(0.0),
        _ => Value::Bits("x".repeat(width(d) as usize)),
    }
}

/// Text-level checks wellen cannot see (it drops repeated values): time stamps
/// strictly increase, the first block is a complete `$dumpvars`, afterwards every
/// written value differs from the previous one of that id and no id appears
/// twice in one time step; only the final time stamp may have no values.
fn check_body(text: &str, nvars: usize) -> Result<(), String> {
    let body = text
        .split("$enddefinitions $end\n")
        .nth(1)
        .ok_or("no $enddefinitions")?;
    let mut last_time: Option<u64> = None;
    let mut last_val: std::collections::HashMap<String, String> = Default::default();
    let mut in_step: std::collections::HashSet<String> = Default::default();
    let mut in_dump = false;
    let mut dumps = 0;
    let mut empty_step_at: Option<u64> = None;
    for line in body.lines() {
        if let Some(t) = line.strip_prefix('#') {
            let t: u64 = t.parse().map_err(|_| format!("bad time stamp {line}"))?;
            if let Some(e) = empty_step_at {
                return Err(format!(
                    "time stamp #{e} without values is not the last one"
                ));
            }
            if last_time.is_some_and(|l| t <= l) {
                return Err(format!("time stamp #{t} after #{last_time:?}"));
            }
            last_time = Some(t);
            in_step.clear();
            empty_step_at = Some(t);
            continue;
        }
        match line {
            "$dumpvars" => {
                if dumps > 0 || !last_val.is_empty() {
                    return Err("$dumpvars not first".into());
                }
                dumps += 1;
                in_dump = true;
                continue;
            }
            "$end" => {
                if in_step.len() != nvars {
                    return Err(format!(
                        "$dumpvars has {} of {} variables",
                        in_step.len(),
                        nvars
                    ));
                }
                in_dump = false;
                continue;
            }
            _ => {}
        }
        empty_step_at = None;
        let (val, id) = if line.starts_with('b') || line.starts_with('r') {
            let (v, id) = line
                .split_once(' ')
                .ok_or(format!("bad value line {line}"))?;
            (v.to_string(), id.to_string())
        } else {
            (line[..1].to_string(), line[1..].to_string())
        };
        if !in_step.insert(id.clone()) {
            return Err(format!("id {id} twice at #{last_time:?}"));
        }
        if !in_dump && last_val.get(&id) == Some(&val) {
            return Err(format!("unchanged value {line} written at #{last_time:?}"));
        }
        if dumps == 0 {
            return Err(format!("value {line} before $dumpvars"));
        }
        last_val.insert(id, val);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, ..ProptestConfig::default() })]

    #[test]
    fn written_vcd_reads_back_as_modelled((decls, steps, window) in case()) {
        let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Ns), "roundtrip").unwrap();
        if let Some((s, e)) = window {
            b.window(s, e).unwrap();
        }
        b.push_scope("top").unwrap();
        b.push_scope("sub").unwrap();
        let mut ids = Vec::new();
        for (i, d) in decls.iter().enumerate() {
            let name = format!("v{i}");
            let id = match d {
                Decl::Bit(t) => b.add_bit(*t, &name, Logic::X).unwrap(),
                Decl::Vector(t, m, l) => b.add_vector(*t, &name, *m, *l, 0).unwrap(),
                Decl::Real => b.add_real(&name, 0.0).unwrap(),
            };
            ids.push(id);
        }
        b.pop_scope().unwrap();
        b.pop_scope().unwrap();
        let mut w = b.start(Vec::new()).unwrap();

        // vectors start as all-x via a change at time 0 (exercises step-0 overrides)
        let mut state: Vec<Value> = decls.iter().map(initial).collect();
        for (i, d) in decls.iter().enumerate() {
            if let Decl::Vector(..) = d {
                w.change_bits(ids[i], &"x".repeat(width(d) as usize)).unwrap();
            }
        }
        // history of (time, full state after the step)
        let mut history: Vec<(u64, Vec<Value>)> = Vec::new();
        let mut t = 0u64;
        // variables assigned in the current step (vectors were assigned x at time 0)
        let mut seen: std::collections::HashSet<usize> = decls
            .iter()
            .enumerate()
            .filter(|(_, d)| matches!(d, Decl::Vector(..)))
            .map(|(i, _)| i)
            .collect();
        for (dt, changes) in &steps {
            if *dt > 0 {
                history.push((t, state.clone()));
                t += dt;
                seen.clear();
            }
            w.set_time(t).unwrap();
            for (i, c) in changes {
                let r = match c {
                    Change::Bit(l) => w.change_bit(ids[*i], *l),
                    Change::Int(v) => w.change_vector(ids[*i], *v),
                    Change::Bits(bits) => w.change_bits(ids[*i], std::str::from_utf8(bits).unwrap()),
                    Change::Real(r) => w.change_real(ids[*i], *r),
                };
                if !seen.insert(*i) {
                    let is_double = matches!(r, Err(WriteError::DoubleChange { .. }));
                    prop_assert!(is_double, "second change of v{} at {} gave {:?}", i, t, r);
                } else {
                    prop_assert!(r.is_ok(), "{:?}", r);
                    state[*i] = to_value(&decls[*i], c);
                }
            }
        }
        history.push((t, state.clone()));
        let text = String::from_utf8(w.finish().unwrap()).unwrap();

        prop_assert_eq!(check_body(&text, decls.len()), Ok(()), "{}", text);

        // reference model
        let (ws, we) = window.unwrap_or((0, u64::MAX));
        let last_time = history.last().map(|h| h.0).unwrap_or(0);
        let wave = Waveform::from_bytes(text.clone().into_bytes()).unwrap();
        prop_assert_eq!(wave.timescale(), Some(Timescale::new(1, TimeUnit::Ns)));
        prop_assert_eq!(wave.signals().len(), decls.len());
        for (i, d) in decls.iter().enumerate() {
            let info = &wave.signals()[i];
            prop_assert_eq!(&info.path, &format!("top.sub.v{i}"));
            prop_assert_eq!(info.width, width(d));
            let kind = if matches!(d, Decl::Real) { SignalKind::Real } else { SignalKind::Bits };
            prop_assert_eq!(info.kind, kind);
            let mut expected: Vec<(u64, Value)> = Vec::new();
            if ws <= last_time {
                // value current at window start
                let at_start = history.iter().rev().find(|(ht, _)| *ht <= ws).map(|h| h.1[i].clone());
                expected.push((ws, at_start.unwrap()));
                for (ht, st) in &history {
                    if *ht > ws && *ht < we && expected.last().map(|e| &e.1) != Some(&st[i]) {
                        expected.push((*ht, st[i].clone()));
                    }
                }
            }
            let got = wave.changes_at(i);
            prop_assert_eq!(&got, &expected, "signal v{} ({:?}) in\n{}", i, d, text);
        }
    }
}
