//! Simulation speed of the X67SM2436 model: ramp-generator cycles of the whole module (both axes) per second,
//! with both axes moving (mode 1 back and forth with jerk limitation and reversing loop on axis 1, speed mode on
//! axis 2) and with both axes idle in Switch on disabled.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use ds402::x67::module::Module;

const CYCLES: u64 = 10_000;

fn enabled_module() -> Module {
    let mut m = Module::new();
    for (name, value) in [
        ("ConfigOutput03a", 30),
        ("ConfigOutput04a", 60),
        ("ConfigOutput05a", 90),
        ("ConfigOutput06a", 30),
        ("ConfigOutput07a", 60),
        ("ConfigOutput08a", 90),
        ("MaxSpeed01pos", 400),
        ("MaxAcc01", 20),
        ("MaxDec01", 25),
        ("JoltTime01", 8),
        ("RevLoop01", 500),
        ("MaxAcc02", 10),
        ("MaxDec02", 10),
    ] {
        m.write_named(name, value).expect("bench register");
    }
    m.set_mode(0, 1);
    m.set_mode(1, 2);
    m.step();
    for cw in [0x0006, 0x0007] {
        m.set_control(0, cw);
        m.set_control(1, cw);
        m.run_ms(1100);
    }
    m.set_control(0, 0x000F);
    m.set_control(1, 0x000F);
    m.step();
    for axis in 0..2 {
        assert_eq!(
            m.status_word(axis) & 0x006F,
            0x0027,
            "axis {axis} in Operation enable"
        );
    }
    m
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("module");
    g.throughput(Throughput::Elements(CYCLES));
    g.bench_function("moving", |b| {
        let mut m = enabled_module();
        b.iter(|| {
            for k in 0..CYCLES {
                if k % 200 == 0 {
                    let target = if (k / 200) % 2 == 0 { 20_000 } else { -5_000 };
                    m.set_abs_pos(0, target);
                    m.set_abs_pos(1, if (k / 200) % 2 == 0 { 300 } else { -300 });
                }
                m.step();
                if k % 200 == 50 {
                    assert_ne!(m.axis(0).observation().ramp.speed, 0, "axis 1 moves");
                }
            }
            m.act_val(0)
        })
    });
    g.bench_function("idle", |b| {
        let mut m = Module::new();
        b.iter(|| {
            m.run(CYCLES as usize);
            m.status_word(0)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
