//! Reader throughput: a generated ESI of at least 2 MB and a generated EDS of at least 1 MB, each parsed
//! from memory; criterion reports MB/s (`cargo bench -p od --bench readers`).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use od::device::DeviceDescription;
use od::{AccessType, DataType, Object, ObjectKind, PdoMapping, SubObject, Value};

/// A device with `records` RECORD objects of 16 entries each in the manufacturer area.
fn big_device(records: u16) -> DeviceDescription {
    let mut desc = DeviceDescription::default();
    desc.identity.vendor_name = "Bench".into();
    desc.identity.product_name = "Bench device".into();
    desc.identity.order_code = "BENCH-1".into();
    desc.dictionary.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
            .with_default(Value::Uint(0x0002_0192)),
    ));
    let types = [
        DataType::Unsigned16,
        DataType::Integer32,
        DataType::Unsigned8,
        DataType::Real32,
    ];
    for r in 0..records {
        let mut o = Object::structured(
            0x2000 + r,
            format!("Parameter block {r}"),
            ObjectKind::Record,
        )
        .with_sub(
            0,
            SubObject::new(
                "Highest sub-index supported",
                DataType::Unsigned8,
                AccessType::Ro,
            )
            .with_default(Value::Uint(16)),
        );
        for s in 1..=16u8 {
            let t = types[s as usize % types.len()];
            let v = match t {
                DataType::Integer32 => Value::Int(-(s as i64) * 1000),
                DataType::Real32 => Value::Real32(s as f32 * 0.5),
                _ => Value::Uint(s as u64),
            };
            let mut sub = SubObject::new(format!("Setting {s} of block {r}"), t, AccessType::Rw)
                .with_default(v)
                .with_pdo(if s % 3 == 0 {
                    PdoMapping::Both
                } else {
                    PdoMapping::None
                });
            if t == DataType::Unsigned16 {
                sub = sub.with_limits(Some(Value::Uint(0)), Some(Value::Uint(1000)));
            }
            o = o.with_sub(s, sub);
        }
        desc.dictionary.insert(o);
    }
    desc
}

fn sized(min_bytes: usize, write: impl Fn(&DeviceDescription) -> String) -> String {
    let mut records = 64;
    loop {
        let text = write(&big_device(records));
        if text.len() >= min_bytes || records >= 0x3FFF {
            return text;
        }
        records *= 2;
    }
}

fn readers(c: &mut Criterion) {
    let esi = sized(2_000_000, od::esi::write);
    let eds = sized(1_000_000, od::eds::write_eds);
    let xdd = sized(1_000_000, od::xdd::write);
    let mut g = c.benchmark_group("readers");
    g.sample_size(20);
    g.throughput(Throughput::Bytes(esi.len() as u64));
    g.bench_function(format!("esi {} bytes", esi.len()), |b| {
        b.iter(|| od::esi::read_all(esi.as_bytes(), "bench.xml").expect("generated ESI reads"))
    });
    g.throughput(Throughput::Bytes(eds.len() as u64));
    g.bench_function(format!("eds {} bytes", eds.len()), |b| {
        b.iter(|| od::eds::read(eds.as_bytes(), "bench.eds").expect("generated EDS reads"))
    });
    g.throughput(Throughput::Bytes(xdd.len() as u64));
    g.bench_function(format!("xdd {} bytes", xdd.len()), |b| {
        b.iter(|| od::xdd::read(xdd.as_bytes(), "bench.xdd").expect("generated XDD reads"))
    });
    g.finish();
}

criterion_group!(benches, readers);
criterion_main!(benches);
