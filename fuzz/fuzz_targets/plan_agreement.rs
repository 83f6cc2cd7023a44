//! The fast path (frame plans, compiled by the generator) against the interpreter: every
//! protocol of every described drive, the same bytes through both (see
//! `vfd_fuzz::plan_agreement`). A difference is a finding.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    vfd_fuzz::plan_agreement(data);
});
