//! The readers (URDF, SRDF, STL, OBJ, COLLADA, URDD JSON) under mutated input: errors, never panics.
//! A short run for CI; `cargo bench --bench fuzz_readers -- EXECS` runs millions (docs/fuzzing.md).

mod common;
#[path = "fuzz/driver.rs"]
mod driver;

#[test]
fn every_reader_survives_mutated_input() {
    let scratch = common::scratch("fuzz");
    driver::quiet_panics();
    for target in driver::targets(&scratch) {
        let outcome = driver::fuzz(&target, 3_000, 1);
        assert_eq!(outcome.execs, 3_000);
        let first = outcome.crashes.first().map(|(input, message)| {
            format!("{message} on input {:?}", String::from_utf8_lossy(input))
        });
        assert!(
            outcome.crashes.is_empty(),
            "{}: {} of {} inputs panicked; first: {}",
            target.name,
            outcome.crashes.len(),
            outcome.execs,
            first.unwrap_or_default()
        );
    }
}
