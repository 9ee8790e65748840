//! Shards: a regression's seed range split into N disjoint contiguous parts, for job arrays
//! (Slurm `sbatch --array`, Kubernetes Indexed Jobs). Part `i` of `n` of `count` seeds from
//! `start` is `[start + i·count/n, start + (i+1)·count/n)` (integer division), so the parts
//! are disjoint, cover the range and differ in size by at most one seed.
//!
//! The index comes from `--shard I/N`, or from the scheduler's environment:
//! `SLURM_ARRAY_TASK_ID` with `SLURM_ARRAY_TASK_COUNT` (or `SLURM_ARRAY_TASK_MIN`/`MAX`: the
//! index is then the task id less the minimum), or with `--shard-count N` (the task id is the
//! index, so `--array=3,17` reruns shards 3 and 17), or `JOB_COMPLETION_INDEX` with
//! `--shard-count N` or `JOB_COMPLETIONS`.

use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
}

impl Shard {
    /// The seeds of this part of `iterations` seeds from `start`. A shard that is not a part
    /// (`count` 0 or `index >= count`, which [`Shard::parse`] and the folder checks refuse) has
    /// none; a range past 2^64 ends there.
    pub fn seeds(&self, start: u64, iterations: u64) -> std::ops::Range<u64> {
        if self.count == 0 || self.index >= self.count {
            return start..start;
        }
        let at = |i: u64| {
            start.saturating_add(
                ((u128::from(i) * u128::from(iterations)) / u128::from(self.count)) as u64,
            )
        };
        at(self.index)..at(self.index + 1)
    }

    /// `I/N` with 0 <= I < N.
    pub fn parse(text: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {text}: expected I/N with 0 <= I < N, e.g. --shard 3/8");
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let (index, count): (u64, u64) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The shard of this process: `--shard`, else the scheduler's environment (`get` reads a
    /// variable), else none. `count_flag` is `--shard-count`.
    pub fn resolve(
        flag: Option<&str>,
        count_flag: Option<u64>,
        get: impl Fn(&str) -> Option<String>,
    ) -> Result<Option<Shard>, String> {
        if let Some(f) = flag {
            if count_flag.is_some() {
                return Err("--shard I/N already gives the count; drop --shard-count".into());
            }
            return Shard::parse(f).map(Some);
        }
        // A variable set but empty is an error, not an absent one: a job array whose index
        // was lost must not run the whole range unsharded.
        let num = |name: &str| -> Result<Option<u64>, String> {
            match get(name) {
                None => Ok(None),
                Some(v) if v.trim().is_empty() => Err(format!("{name} is set but empty; it must be a whole number (unset it outside a job array)")),
                Some(v) => v.trim().parse().map(Some).map_err(|_| format!("{name}={v} is not a whole number (0 to {})", u64::MAX)),
            }
        };
        let check = |index: u64, count: u64, what: &str| -> Result<Option<Shard>, String> {
            if count == 0 || index >= count {
                Err(format!(
                    "{what}: index {index} is not below the count {count}"
                ))
            } else {
                Ok(Some(Shard { index, count }))
            }
        };
        if let Some(task) = num("SLURM_ARRAY_TASK_ID")? {
            // With --shard-count the task ids are the shard indices themselves (`--array=3,17`
            // resubmits shards 3 and 17); without it, the array is 0..N or MIN..MAX.
            let min = if count_flag.is_some() {
                0
            } else {
                num("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0)
            };
            let count = match (count_flag, num("SLURM_ARRAY_TASK_COUNT")?, num("SLURM_ARRAY_TASK_MAX")?) {
                (Some(c), _, _) | (None, Some(c), _) => c,
                (None, None, Some(max)) => max
                    .checked_sub(min)
                    .ok_or("SLURM_ARRAY_TASK_MAX is below SLURM_ARRAY_TASK_MIN")?
                    .checked_add(1)
                    .ok_or_else(|| format!("SLURM_ARRAY_TASK_MAX={max} with SLURM_ARRAY_TASK_MIN={min}: more than {} tasks", u64::MAX))?,
                (None, None, None) => return Err("inside a Slurm array (SLURM_ARRAY_TASK_ID is set) but neither SLURM_ARRAY_TASK_COUNT nor SLURM_ARRAY_TASK_MAX says how many tasks: give --shard-count N".into()),
            };
            let index = task
                .checked_sub(min)
                .ok_or("SLURM_ARRAY_TASK_ID is below SLURM_ARRAY_TASK_MIN")?;
            return check(index, count, "Slurm array task");
        }
        if let Some(index) = num("JOB_COMPLETION_INDEX")? {
            let count = match (count_flag, num("JOB_COMPLETIONS")?) {
                (Some(c), _) | (None, Some(c)) => c,
                (None, None) => return Err("inside a Kubernetes Indexed Job (JOB_COMPLETION_INDEX is set) but the number of shards is unknown: give --shard-count N (the Job's completions)".into()),
            };
            return check(index, count, "Kubernetes Indexed Job");
        }
        if count_flag.is_some() {
            return Err("--shard-count needs a shard index: --shard I/N, or SLURM_ARRAY_TASK_ID / JOB_COMPLETION_INDEX from the scheduler".into());
        }
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The parts are disjoint, in order, and their union is the range.
        #[test]
        fn parts_partition_the_range(start in 0u64..1_000_000, iterations in 0u64..10_000, count in 1u64..300) {
            let mut next = start;
            for index in 0..count {
                let r = Shard { index, count }.seeds(start, iterations);
                prop_assert_eq!(r.start, next);
                prop_assert!(r.end - r.start <= iterations / count + 1);
                next = r.end;
            }
            prop_assert_eq!(next, start + iterations);
        }
    }

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| {
            vars.iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn the_index_comes_from_the_flag_slurm_or_kubernetes() {
        assert_eq!(
            Shard::resolve(Some("2/5"), None, env(&[])),
            Ok(Some(Shard { index: 2, count: 5 }))
        );
        assert_eq!(
            Shard::resolve(
                None,
                None,
                env(&[
                    ("SLURM_ARRAY_TASK_ID", "3"),
                    ("SLURM_ARRAY_TASK_COUNT", "4")
                ])
            ),
            Ok(Some(Shard { index: 3, count: 4 }))
        );
        // --array=1-8: ids 1..8, index = id - min
        assert_eq!(
            Shard::resolve(
                None,
                None,
                env(&[
                    ("SLURM_ARRAY_TASK_ID", "8"),
                    ("SLURM_ARRAY_TASK_MIN", "1"),
                    ("SLURM_ARRAY_TASK_MAX", "8")
                ])
            ),
            Ok(Some(Shard { index: 7, count: 8 }))
        );
        assert_eq!(
            Shard::resolve(None, Some(10), env(&[("JOB_COMPLETION_INDEX", "9")])),
            Ok(Some(Shard {
                index: 9,
                count: 10
            }))
        );
        // a resubmission of shards 3 and 17 of 100: the task id is the index
        let resub = [
            ("SLURM_ARRAY_TASK_ID", "17"),
            ("SLURM_ARRAY_TASK_MIN", "3"),
            ("SLURM_ARRAY_TASK_MAX", "17"),
            ("SLURM_ARRAY_TASK_COUNT", "2"),
        ];
        assert_eq!(
            Shard::resolve(None, Some(100), env(&resub)),
            Ok(Some(Shard {
                index: 17,
                count: 100
            }))
        );
        assert_eq!(
            Shard::resolve(
                None,
                None,
                env(&[("JOB_COMPLETION_INDEX", "0"), ("JOB_COMPLETIONS", "3")])
            ),
            Ok(Some(Shard { index: 0, count: 3 }))
        );
        assert_eq!(Shard::resolve(None, None, env(&[])), Ok(None));
    }

    #[test]
    fn scheduler_variables_that_would_wrap_or_are_empty_are_refused() {
        let max = u64::MAX.to_string();
        let e = Shard::resolve(
            None,
            None,
            env(&[("SLURM_ARRAY_TASK_ID", "0"), ("SLURM_ARRAY_TASK_MAX", &max)]),
        )
        .unwrap_err();
        assert!(
            e.contains("more than") && e.contains("SLURM_ARRAY_TASK_MAX=18446744073709551615"),
            "{e}"
        );
        for (vars, name) in [
            (
                vec![("SLURM_ARRAY_TASK_ID", ""), ("SLURM_ARRAY_TASK_COUNT", "4")],
                "SLURM_ARRAY_TASK_ID",
            ),
            (
                vec![("SLURM_ARRAY_TASK_ID", " "), ("SLURM_ARRAY_TASK_MAX", "3")],
                "SLURM_ARRAY_TASK_ID",
            ),
            (
                vec![("JOB_COMPLETION_INDEX", ""), ("JOB_COMPLETIONS", "4")],
                "JOB_COMPLETION_INDEX",
            ),
            (
                vec![("SLURM_ARRAY_TASK_ID", "2"), ("SLURM_ARRAY_TASK_COUNT", "")],
                "SLURM_ARRAY_TASK_COUNT",
            ),
        ] {
            let e = Shard::resolve(None, None, env(&vars)).unwrap_err();
            assert!(
                e.contains(&format!("{name} is set but empty")),
                "{vars:?}: {e}"
            );
        }
        // Not a part: no seed, never a panic or a wrap.
        assert_eq!(Shard { index: 0, count: 0 }.seeds(5, 100), 5..5);
        assert_eq!(Shard { index: 7, count: 3 }.seeds(5, 100), 5..5);
        assert_eq!(
            Shard { index: 1, count: 2 }.seeds(u64::MAX - 10, 100).end,
            u64::MAX
        );
    }

    #[test]
    fn bad_shards_say_what_is_valid() {
        for f in ["5/5", "1/0", "x/2", "3", "-1/4"] {
            assert!(
                Shard::resolve(Some(f), None, env(&[]))
                    .unwrap_err()
                    .contains("0 <= I < N"),
                "{f}"
            );
        }
        assert!(
            Shard::resolve(None, None, env(&[("SLURM_ARRAY_TASK_ID", "3")]))
                .unwrap_err()
                .contains("--shard-count")
        );
        assert!(Shard::resolve(
            None,
            None,
            env(&[("JOB_COMPLETION_INDEX", "3"), ("JOB_COMPLETIONS", "3")])
        )
        .unwrap_err()
        .contains("not below"));
        assert!(Shard::resolve(None, Some(4), env(&[]))
            .unwrap_err()
            .contains("needs a shard index"));
        assert!(Shard::resolve(
            None,
            None,
            env(&[
                ("SLURM_ARRAY_TASK_ID", "abc"),
                ("SLURM_ARRAY_TASK_COUNT", "4")
            ])
        )
        .unwrap_err()
        .contains("not a whole number"));
    }
}
