//! The readers' fuzz run: `cargo bench --bench fuzz_readers -- [EXECS] [SEED] [READER]` (default
//! 1,000,000 inputs per reader, seed 1, every reader), the readers in parallel. Prints execs, crashes and time per reader; crashing
//! inputs go to target/fuzz-crashes/. Exits 1 if any reader crashed.

#[path = "../tests/fuzz/driver.rs"]
mod driver;

use rayon::prelude::*;

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let execs: u64 = args
        .first()
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    let seed: u64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1);
    let scratch = std::env::temp_dir().join(format!("scm-fuzz-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    driver::quiet_panics();
    let only = args.get(2).cloned();
    let targets: Vec<_> = driver::targets(&scratch)
        .into_iter()
        .filter(|t| only.as_deref().is_none_or(|o| o == t.name))
        .collect();
    let outcomes: Vec<_> = targets
        .par_iter()
        .map(|t| (t.name, driver::fuzz(t, execs, seed)))
        .collect();
    let crashes_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fuzz-crashes");
    println!("| reader | execs | crashes | seconds | execs/s | slowest input |");
    println!("|---|---|---|---|---|---|");
    let mut crashed = false;
    for (name, o) in &outcomes {
        println!(
            "| {name} | {} | {} | {:.1} | {:.0} | {:.1} ms |",
            o.execs,
            o.crashes.len(),
            o.seconds,
            o.execs as f64 / o.seconds,
            o.slowest.as_secs_f64() * 1e3
        );
        for (k, (input, message)) in o.crashes.iter().enumerate().take(20) {
            crashed = true;
            let _ = std::fs::create_dir_all(&crashes_dir);
            let _ = std::fs::write(crashes_dir.join(format!("{name}-{k}.bin")), input);
            eprintln!("{name} crash {k}: {message}");
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    if crashed {
        std::process::exit(1);
    }
}
