//! The commands of `pmu50`, one file each: its options (`Args`) and its `run`, which returns
//! what the command ended with ([`error::Outcome`]) or why it could not ([`error::CliError`]).
//! `main` turns either into the exit code, once.

pub mod common;
pub mod error;
pub mod io;

pub mod budget;
pub mod cache;
pub mod check;
pub mod closure;
pub mod diff;
pub mod grade;
pub mod hdl;
pub mod history;
pub mod lint;
pub mod list;
pub mod lockstep;
pub mod merge;
pub mod mutation;
pub mod random;
pub mod regress;
pub mod rtl_files;
pub mod rtl_info;
pub mod rtl_map;
pub mod run;
pub mod seal;
pub mod signoff;
pub mod speed_limit;
pub mod vectors;
pub mod waivers;
pub mod xprop;
