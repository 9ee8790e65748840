//! The text of a VCD body, written without a branch per character: a variable's change line
//! ([`ChangeLine`]) and a time stamp ([`stamp`]), each written at the start of a fixed window of
//! [`SLACK`] bytes of an output buffer (the caller keeps that many bytes free past its position,
//! so no write checks its length).
//!
//! [`Stamps`] writes a time stamp from the last one when the clock's step repeats: the last
//! stamp's digits plus the step's, one decimal digit a byte of a `u64` (with 246 added to every
//! byte, a digit sum of 10 or more carries into the next byte by itself); any other time goes
//! through [`stamp`].
//!
//! [`crate::writer::VcdOut`] writes every change of the checked writer with these.

/// `b"00000000"` .. `b"11111111"`: the 8 VCD bits of each byte value, msb first.
const BITS8: [[u8; 8]; 256] = {
    let mut t = [[b'0'; 8]; 256];
    let mut v = 0;
    while v < 256 {
        let mut k = 0;
        while k < 8 {
            if (v >> (7 - k)) & 1 == 1 {
                t[v][k] = b'1';
            }
            k += 1;
        }
        v += 1;
    }
    t
};

/// Longest identifier code a [`ChangeLine`] holds: with the space before it and the newline
/// after it, its suffix is 16 bytes. Variables with longer codes, and vectors wider than 64
/// bits, have none (the writer's general path).
pub const CODE: usize = 14;

/// Bytes one change line may touch past its start: `b`, 64 bits and the 16-byte suffix store
/// (the 8-character chunks of the bits are written whole, 8 of them at most, and the suffix
/// overwrites what the last chunk wrote beyond the width).
const LINE: usize = 1 + 64 + 16;

/// Bytes that must be free at the output position before [`ChangeLine::write`] or [`stamp`]:
/// one change line or one time stamp fits.
pub const SLACK: usize = 128;
const _: () = assert!(SLACK >= LINE && SLACK >= 26);

/// The change line of a variable of at most 64 bits, `b<bits> <code>\n` (vector) or
/// `<bit><code>\n` (scalar), as the text after the value: `suffix` holds ` <code>\n` or
/// `<code>\n` in its first `len` bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChangeLine {
    suffix: [u8; 16],
    len: u8,
    /// 1: a scalar's line (no `b`); 2..=64: a vector's
    width: u8,
}

impl ChangeLine {
    /// The writer's mark of a variable without a line (width 0): its changes take the general
    /// path.
    pub(crate) const GENERAL: ChangeLine = ChangeLine {
        suffix: [0; 16],
        len: 0,
        width: 0,
    };

    /// False for [`ChangeLine::GENERAL`].
    #[inline(always)]
    pub(crate) fn is_line(&self) -> bool {
        self.width > 0
    }

    /// The line of a variable with identifier `code` and `width` bits; `None` for a width of 0
    /// or over 64 bits, a code longer than [`CODE`] (those take the writer's general path), and
    /// a code that is not an identifier code of VCD (empty, or a byte outside the printable
    /// ASCII characters `!` to `~`).
    pub fn new(code: &[u8], width: u32) -> Option<ChangeLine> {
        if !(1..=64).contains(&width)
            || code.is_empty()
            || code.len() > CODE
            || !code.iter().all(|b| (b'!'..=b'~').contains(b))
        {
            return None;
        }
        let text: Vec<u8> = if width == 1 {
            [code, b"\n"].concat()
        } else {
            [&b" "[..], code, b"\n"].concat()
        };
        let mut suffix = [0; 16];
        suffix[..text.len()].copy_from_slice(&text);
        Some(ChangeLine {
            suffix,
            len: text.len() as u8,
            width: width as u8,
        })
    }

    /// `line` (one line, its `\n` included) is a change line of this variable.
    pub(crate) fn is_line_of(&self, line: &[u8]) -> bool {
        let len = usize::from(self.len);
        let value = if self.width == 1 {
            1
        } else {
            1 + usize::from(self.width)
        };
        line.len() == value + len && line.ends_with(&self.suffix[..len])
    }

    /// Write the line with two-state value `v` at the start of `out`; returns its length. `v`
    /// must fit the width (the checked writer has compared it; a wider value's extra bits are
    /// dropped).
    #[inline(always)]
    pub fn write(&self, out: &mut [u8; SLACK], v: u64) -> usize {
        if self.width == 1 {
            return self.scalar(out, v);
        }
        // The bits msb first from `out[1]`, in whole chunks of 8 characters (the value fits the
        // width, so the characters past it are the chunk's low bits, overwritten by the suffix).
        let w = usize::from(self.width);
        out[0] = b'b';
        let u = v << (64 - w);
        // Two chunks whatever the width (most variables have at most 16 bits; for 8 or fewer
        // the second is overwritten by the suffix), the others only for wider variables.
        chunk(out, u, 0);
        chunk(out, u, 1);
        if w > 16 {
            let mut j = 2;
            while j < 8 && 8 * j < w {
                chunk(out, u, j);
                j += 1;
            }
        }
        self.suffix_after(out, w)
    }

    /// [`ChangeLine::write`] for a variable the caller knows to be `W` bits wide (asserted in
    /// debug builds): the same text, with the tests and shifts of the width resolved at compile
    /// time (a scalar's line or a vector's, how many chunks of eight bits, where the suffix
    /// goes).
    #[inline(always)]
    pub fn write_w<const W: usize>(&self, out: &mut [u8; SLACK], v: u64) -> usize {
        debug_assert_eq!(
            usize::from(self.width),
            W,
            "write_w: a line of {} bits written as {W}",
            self.width
        );
        if W == 1 {
            return self.scalar(out, v);
        }
        out[0] = b'b';
        let u = v.wrapping_shl((64 - W) as u32);
        let mut j = 0;
        while 8 * j < W {
            chunk(out, u, j);
            j += 1;
        }
        self.suffix_after(out, W)
    }

    /// A scalar's line: its bit, the code, the newline; returns the length.
    #[inline(always)]
    fn scalar(&self, out: &mut [u8; SLACK], v: u64) -> usize {
        out[0] = b'0' + (v & 1) as u8;
        out[1..17].copy_from_slice(&self.suffix);
        1 + usize::from(self.len)
    }

    /// A vector's suffix after its `b` and `w` bits; returns the line's length.
    #[inline(always)]
    fn suffix_after(&self, out: &mut [u8; SLACK], w: usize) -> usize {
        out[1 + w..17 + w].copy_from_slice(&self.suffix);
        1 + w + usize::from(self.len)
    }
}

/// Chunk `j` of the bits of `u` (the value shifted to the top of the word), eight characters
/// from `out[1 + 8 * j]`.
#[inline(always)]
fn chunk(out: &mut [u8; SLACK], u: u64, j: usize) {
    out[1 + 8 * j..9 + 8 * j].copy_from_slice(&BITS8[(u >> (56 - 8 * j)) as usize & 0xFF]);
}

/// `00` .. `99`: the two decimal digits of each value below 100.
const DIGITS2: [[u8; 2]; 100] = {
    let mut t = [[b'0'; 2]; 100];
    let mut v = 0;
    while v < 100 {
        t[v] = [b'0' + (v / 10) as u8, b'0' + (v % 10) as u8];
        v += 1;
    }
    t
};

/// `b'0'` in every byte of a `u64`.
const ASCII0: u64 = 0x3030_3030_3030_3030;

/// The eight decimal digits of `x` (< 10^8, leading zeros included) as the bytes of a `u64`,
/// most significant digit in the lowest byte (first in memory as `to_le_bytes`), each byte
/// 0..=9: `x` split into two groups of four digits in 32-bit lanes, those into groups of two in
/// 16-bit lanes, those into digits in bytes; each division by a constant is a multiply and a
/// shift that is exact over the lane's range (`x / 100 = x * 10486 >> 20` for `x < 10^4`,
/// `x / 10 = x * 103 >> 10` for `x < 100`).
#[inline(always)]
fn digits8(x: u32) -> u64 {
    let x = u64::from(x);
    let merged = (x / 10_000) | ((x % 10_000) << 32);
    let top = ((merged * 10_486) >> 20) & 0x0000_007F_0000_007F;
    let hundreds = ((merged - 100 * top) << 16) + top;
    let tens = ((hundreds * 103) >> 10) & 0x000F_000F_000F_000F;
    tens + ((hundreds - 10 * tens) << 8)
}

/// Write `#t\n` at the start of `out`; returns its length (at most 22 bytes). Up to 10^16 the
/// decimal digits come eight at a time, computed in the lanes of a `u64` ([`digits8`]), the
/// leading zeros of the first group shifted out; beyond that a loop.
#[inline(always)]
pub fn stamp(out: &mut [u8; SLACK], t: u64) -> usize {
    const E8: u64 = 100_000_000;
    out[0] = b'#';
    let (first, rest) = if t < E8 {
        (t, None)
    } else if t < E8 * E8 {
        (t / E8, Some(t % E8))
    } else {
        return stamp_long(out, t);
    };
    let d = digits8(first as u32);
    // leading zero digits of the first group (t = 0 keeps its last digit)
    let lead = if first == 0 {
        7
    } else {
        (d.trailing_zeros() / 8) as usize
    };
    out[1..9].copy_from_slice(&((d | ASCII0) >> (8 * lead)).to_le_bytes());
    let mut n = 1 + 8 - lead;
    if let Some(r) = rest {
        out[n..n + 8].copy_from_slice(&(digits8(r as u32) | ASCII0).to_le_bytes());
        n += 8;
    }
    out[n] = b'\n';
    n + 1
}

/// Time stamps written one after the other, each from the last one when it is the same step
/// later (a clock): `t`'s digits are the last stamp's plus the step's, added in the bytes of a
/// `u64` (one decimal digit a byte, least significant first) with the carries done by the
/// adder itself; any other stamp by [`stamp`]. The text is always [`stamp`]'s.
#[derive(Clone, Copy, Debug)]
pub struct Stamps {
    /// the last stamp's time and its digits (when below 10^8)
    last: u64,
    digits: u64,
    /// the last step (`u64::MAX`: none) and its digits
    step: u64,
    step_digits: u64,
}

impl Default for Stamps {
    fn default() -> Stamps {
        Stamps::new()
    }
}

impl Stamps {
    /// No stamp written yet.
    pub const fn new() -> Stamps {
        Stamps {
            last: 0,
            digits: 0,
            step: u64::MAX,
            step_digits: 0,
        }
    }

    /// Write `#t\n` at the start of `out` (as [`stamp`]); returns its length.
    #[inline(always)]
    pub fn write(&mut self, out: &mut [u8; SLACK], t: u64) -> usize {
        const E8: u64 = 100_000_000;
        if t.wrapping_sub(self.last) == self.step && t < E8 {
            // Decimal addition of two numbers below 10^8 whose sum is below 10^8: each byte
            // holds a digit sum 0..=18 plus a carry; with 246 added to every byte a sum of 10 or
            // more carries into the next byte by itself and leaves its digit, and a smaller one
            // is left at 246 or more (its top bit set), which takes the 246 back.
            let x = self.digits + self.step_digits + 0xF6F6_F6F6_F6F6_F6F6;
            let fix = ((x >> 7) & 0x0101_0101_0101_0101) * 0xF6;
            let digits = x - fix;
            self.last = t;
            self.digits = digits;
            out[0] = b'#';
            // most significant digit first, its leading zeros shifted out (0 keeps one digit)
            let d = digits.swap_bytes();
            let lead = if digits == 0 {
                7
            } else {
                (digits.leading_zeros() / 8) as usize
            };
            out[1..9].copy_from_slice(&((d | ASCII0) >> (8 * lead)).to_le_bytes());
            let n = 9 - lead;
            out[n] = b'\n';
            return n + 1;
        }
        self.restart(t);
        stamp(out, t)
    }

    /// The digits of `t` and of its step from the last stamp, for the next stamp.
    #[cold]
    #[inline(never)]
    fn restart(&mut self, t: u64) {
        const E8: u64 = 100_000_000;
        let step = t.wrapping_sub(self.last);
        if t < E8 && step < E8 {
            self.step = step;
            self.step_digits = digits8(step as u32).swap_bytes();
            self.digits = digits8(t as u32).swap_bytes();
            self.last = t;
        } else {
            *self = Stamps::new();
        }
    }
}

/// A time stamp of 10^16 or later: two digits per division.
#[cold]
#[inline(never)]
fn stamp_long(out: &mut [u8; SLACK], mut t: u64) -> usize {
    let mut d = [0u8; 24];
    d[23] = b'\n';
    let mut k = 23;
    while t >= 100 {
        k -= 2;
        d[k..k + 2].copy_from_slice(&DIGITS2[(t % 100) as usize]);
        t /= 100;
    }
    if t >= 10 {
        k -= 2;
        d[k..k + 2].copy_from_slice(&DIGITS2[t as usize]);
    } else {
        k -= 1;
        d[k] = b'0' + t as u8;
    }
    out[1..25 - k].copy_from_slice(&d[k..]);
    25 - k
}

#[cfg(test)]
mod tests {
    use super::{digits8, stamp, ChangeLine, Stamps, ASCII0, SLACK};

    /// `Stamps` writes what `stamp` writes: clocks of many periods across every power of ten
    /// below 10^9 (carries through every digit), from 0 and from just below each power, and
    /// irregular steps, backwards steps and repeats between them.
    #[test]
    fn stamps_from_the_last_one_are_stamps() {
        let check = |times: &mut dyn Iterator<Item = u64>| {
            let mut s = Stamps::new();
            for t in times {
                let (mut a, mut b) = ([0u8; SLACK], [0u8; SLACK]);
                let (na, nb) = (s.write(&mut a, t), stamp(&mut b, t));
                assert_eq!(&a[..na], &b[..nb], "t = {t}");
            }
        };
        for period in [1u64, 2, 3, 7, 10, 99, 100, 999, 1000, 12_345, 99_999_999] {
            check(&mut (0..3000).map(|k| k * period));
            for e in 1..=9 {
                let p = 10u64.pow(e);
                check(&mut (0..300).map(|k| p.saturating_sub(period * 150) + k * period));
            }
        }
        let mut x = 1u64;
        let mut irregular = Vec::new();
        let mut t = 0u64;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            // mostly a clock of 10, now and then another step, a repeat, a step back or a jump
            t = match x % 50 {
                0 => t + x % 1000,
                1 => t,
                2 => t.saturating_sub(x % 100),
                3 => x % 200_000_000,
                4 => x,
                _ => t + 10,
            };
            irregular.push(t);
        }
        check(&mut irregular.into_iter());
    }

    /// `digits8` is the zero-padded decimal of every group of eight digits: every value below
    /// 10^5, every power of ten and its neighbours, and a stride through the rest.
    #[test]
    fn digits8_is_the_zero_padded_decimal() {
        let pow = (0..8).flat_map(|e| {
            let p = 10u32.pow(e);
            [p - 1, p, p + 1, 2 * p - 1, 5 * p, 10 * p - 1]
        });
        let all = (0..100_000)
            .chain((0..100_000_000).step_by(9_973))
            .chain(pow)
            .chain([99_999_999]);
        for x in all {
            let got = (digits8(x) | ASCII0).to_le_bytes();
            assert_eq!(std::str::from_utf8(&got).unwrap(), format!("{x:08}"), "{x}");
        }
    }

    /// A time stamp is `#`, the decimal time without leading zeros, a newline: around every
    /// power of ten (both sides of the eight-digit groups and of the long path) and at the
    /// ends of the range.
    #[test]
    fn stamps_are_decimal() {
        let mut ts: Vec<u64> = vec![0, 1, 9, 10, u64::MAX, u64::MAX - 1];
        for e in 1..20 {
            let p = 10u64.pow(e);
            ts.extend([p - 1, p, p + 1, 3 * (p / 10) + 7]);
        }
        for t in ts {
            let mut out = [0u8; SLACK];
            let n = stamp(&mut out, t);
            assert_eq!(
                std::str::from_utf8(&out[..n]).unwrap(),
                format!("#{t}\n"),
                "{t}"
            );
        }
    }

    /// A change line is the value's bits (scalar: one character; vector: `b`, msb first, no
    /// leading zeros dropped), the code and a newline, for every width up to 64 and values at
    /// both ends of each width.
    #[test]
    fn change_lines_are_the_bits_and_the_code() {
        for w in 1..=64u32 {
            for code in [&b"!"[..], b"abcdefghijklmn"] {
                let l = ChangeLine::new(code, w).expect("a line up to 64 bits and 14 characters");
                let max = if w == 64 { u64::MAX } else { (1 << w) - 1 };
                for v in [0, 1, max, max / 3, max - 1] {
                    let mut out = [b'?'; SLACK];
                    let n = l.write(&mut out, v);
                    let code = std::str::from_utf8(code).unwrap();
                    let want = if w == 1 {
                        format!("{v}{code}\n")
                    } else {
                        format!("b{:0w$b} {code}\n", v, w = w as usize)
                    };
                    assert_eq!(
                        std::str::from_utf8(&out[..n]).unwrap(),
                        want,
                        "width {w} value {v}"
                    );
                }
            }
        }
        assert_eq!(ChangeLine::new(b"!", 65), None);
        assert_eq!(ChangeLine::new(b"!", 0), None);
        assert_eq!(ChangeLine::new(b"abcdefghijklmno", 8), None);
        assert_eq!(ChangeLine::new(b"", 8), None);
        assert_eq!(ChangeLine::new(b"a b", 8), None);
        assert_eq!(ChangeLine::new(b"a\n", 1), None);
    }

    /// `write_w` (the width known at compile time) writes what `write` writes, for widths at
    /// both sides of each chunk of eight bits, values at both ends of each width and a stride of
    /// values between, two code lengths.
    #[test]
    fn change_lines_of_a_known_width_are_the_same_lines() {
        fn check<const W: usize>() {
            for code in [&b"!"[..], b"abcdefghijklmn"] {
                let l = ChangeLine::new(code, W as u32)
                    .expect("a line up to 64 bits and 14 characters");
                let max = u64::MAX >> (64 - W);
                let mut x = 0x9E37_79B9_7F4A_7C15u64;
                let stride = (0..200).map(|_| {
                    x ^= x << 13;
                    x ^= x >> 7;
                    x ^= x << 17;
                    x & max
                });
                for v in [0, 1, max, max / 3, max - 1].into_iter().chain(stride) {
                    let (mut a, mut b) = ([b'?'; SLACK], [b'?'; SLACK]);
                    let (na, nb) = (l.write(&mut a, v), l.write_w::<W>(&mut b, v));
                    assert_eq!(&a[..na], &b[..nb], "width {W} value {v:#x}");
                }
            }
        }
        check::<1>();
        check::<2>();
        check::<3>();
        check::<7>();
        check::<8>();
        check::<9>();
        check::<15>();
        check::<16>();
        check::<17>();
        check::<24>();
        check::<31>();
        check::<32>();
        check::<33>();
        check::<63>();
        check::<64>();
    }
}
