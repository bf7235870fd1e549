//! The reference workload `scripts/bench-check` measures in the same run as the benchmarks it checks:
//! a fixed CPU- and memory-bound piece of work with no code of this workspace in it (a pseudo-random
//! buffer of 4 MiB hashed, copied and sorted, and 64 Ki small vectors allocated, filled and freed).
//! A benchmark's time divided by this one's is what a slower or busier machine changes little.
//!
//! `cargo bench -p testkit --bench reference [-- ROUNDS]` (default 31; one under `cargo test`) prints one line:
//! `reference: N ns per round (fastest of R rounds; median M ns)`: the fastest round is the one
//! least held up by other work on the machine.

use std::hint::black_box;
use std::time::Instant;

const WORDS: usize = 1 << 19;

/// xorshift64*: the same buffer on every machine and every run.
fn buffer() -> Vec<u64> {
    let mut x = 0x9E37_79B9_7F4A_7C15u64;
    (0..WORDS)
        .map(|_| {
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            x.wrapping_mul(0x2545_F491_4F6C_DD1D)
        })
        .collect()
}

/// FNV-1a over the bytes of `words`.
fn fnv(words: &[u64]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for w in words {
        for b in w.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

/// One round: hash, copy and sort, hash again, then small allocations.
fn round(data: &[u64]) -> u64 {
    let mut h = fnv(data);
    let mut sorted = data.to_vec();
    sorted.sort_unstable();
    h ^= fnv(&sorted);
    let mut total = 0u64;
    for k in 0..(1u64 << 16) {
        let v: Vec<u64> = (0..(k % 32) + 1).map(|i| i ^ h).collect();
        total = total.wrapping_add(black_box(v).iter().fold(0u64, |a, &b| a.wrapping_add(b)));
    }
    h ^ total
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // `cargo test` runs this target without `--bench`: one round then, to show it runs.
    let default = if args.iter().any(|a| a == "--bench") {
        31
    } else {
        1
    };
    let rounds: usize = args.iter().find_map(|a| a.parse().ok()).unwrap_or(default);
    let data = buffer();
    black_box(round(black_box(&data)));
    let mut times: Vec<u128> = (0..rounds)
        .map(|_| {
            let t = Instant::now();
            black_box(round(black_box(&data)));
            t.elapsed().as_nanos()
        })
        .collect();
    times.sort_unstable();
    println!(
        "reference: {} ns per round (fastest of {rounds} rounds; median {} ns)",
        times[0],
        times[rounds / 2]
    );
}
