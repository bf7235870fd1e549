//! Reading time against the layout of the text: the same ESI and XDD with their line breaks and written
//! on one line, and an EDS with and without one very long line of the same size. A reader's time
//! follows the size of the file, not the length of its lines, so the two cases of each pair should be
//! about as fast (`cargo bench -p od --bench layout`).
//!
//! The generated cases always run; `weidmueller-UR20_IO.xml` from the shared corpus beside the
//! checkout (`../shared/corpus/esi`) is read too when it is there.

use std::path::Path;

use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use od::device::DeviceDescription;
use od::{AccessType, DataType, Object, ObjectKind, SubObject, Value};

/// A device with `records` RECORD objects of 8 entries each, their names with characters of more than
/// one byte (so that a column, which counts characters, is not a byte count).
fn device(records: u16) -> DeviceDescription {
    let mut desc = DeviceDescription::default();
    desc.identity.vendor_name = "Bench Größe".into();
    desc.identity.product_name = "Bench device µ".into();
    desc.identity.order_code = "BENCH-2".into();
    desc.dictionary.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
            .with_default(Value::Uint(0x0002_0192)),
    ));
    for r in 0..records {
        let mut o = Object::structured(
            0x2000 + r,
            format!("Block {r} — Temperatur °C"),
            ObjectKind::Record,
        )
        .with_sub(
            0,
            SubObject::new(
                "Highest sub-index supported",
                DataType::Unsigned8,
                AccessType::Ro,
            )
            .with_default(Value::Uint(8)),
        );
        for s in 1..=8u8 {
            o = o.with_sub(
                s,
                SubObject::new(
                    format!("Grenzwert {s} (µs) of block {r}"),
                    DataType::Unsigned16,
                    AccessType::Rw,
                )
                .with_default(Value::Uint(s as u64)),
            );
        }
        desc.dictionary.insert(o);
    }
    desc
}

/// `xml` with the line breaks and indentation between tags left out: the same document on one line.
fn one_line(xml: &str) -> String {
    let mut out = String::with_capacity(xml.len());
    let mut rest = xml;
    while let Some(nl) = rest.find('\n') {
        let (line, after) = rest.split_at(nl);
        let line = line.strip_suffix('\r').unwrap_or(line);
        let next = after[1..].trim_start_matches([' ', '\t', '\r', '\n']);
        if line.trim_end().ends_with('>') && next.starts_with('<') {
            out.push_str(line.trim_end());
            rest = next;
        } else {
            out.push_str(line);
            out.push('\n');
            rest = &after[1..];
        }
    }
    out.push_str(rest);
    out
}

/// `eds` with an object whose name is one line of about `extra` bytes.
fn eds_long_line(eds: &str, extra: usize) -> String {
    let unit = "Grenzwert µs °C ";
    let filler = unit.repeat(extra.div_ceil(unit.len()));
    format!(
        "{eds}\n[5FFF]\nParameterName=Long text {filler}\nObjectType=0x7\nDataType=0x0009\nAccessType=ro\nDefaultValue=x\n"
    )
}

/// `eds` with objects of short names that add about as many bytes as [`eds_long_line`] adds.
fn eds_many_lines(eds: &str, extra: usize) -> String {
    let line = "Grenzwert µs °C ".repeat(4);
    let mut out = format!("{eds}\n");
    let mut added = 0;
    let mut n = 0;
    while added < extra {
        let section = format!(
            "[{:04X}]\nParameterName=Text {n} {line}\nObjectType=0x7\nDataType=0x0009\nAccessType=ro\nDefaultValue=x\n",
            0x5000 + n
        );
        added += section.len();
        out.push_str(&section);
        n += 1;
    }
    out
}

fn pair<F>(
    g: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    text: &str,
    read: F,
) where
    F: Fn(&[u8]) + Copy,
{
    let flat = one_line(text);
    assert!(flat.lines().count() <= 2, "{name} is on one line");
    for (layout, t) in [("lines", text), ("one line", flat.as_str())] {
        g.throughput(Throughput::Bytes(t.len() as u64));
        g.bench_function(format!("{name} {layout} {} bytes", t.len()), |b| {
            b.iter(|| read(t.as_bytes()))
        });
    }
}

fn layout(c: &mut Criterion) {
    let desc = device(600);
    let esi = od::esi::write(&desc);
    let xdd = od::xdd::write(&desc);
    let eds = od::eds::write_eds(&desc);
    let mut g = c.benchmark_group("layout");
    g.sample_size(10);
    pair(&mut g, "esi", &esi, |t| {
        od::esi::read_file(t, "bench.xml").expect("generated ESI reads");
    });
    pair(&mut g, "xdd", &xdd, |t| {
        od::xdd::read_file(t, "bench.xdd").expect("generated XDD reads");
    });
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/corpus/esi/weidmueller-UR20_IO.xml");
    match std::fs::read(&corpus) {
        Ok(bytes) => {
            let text = String::from_utf8(bytes).expect("the corpus ESI is UTF-8");
            pair(&mut g, "UR20 esi", &text, |t| {
                od::esi::read_file(t, "UR20.xml").expect("the corpus ESI reads");
            });
        }
        Err(e) => eprintln!("{}: {e}; its case is left out", corpus.display()),
    }
    let extra = 1_000_000;
    for (layout, t) in [
        ("lines", eds_many_lines(&eds, extra)),
        ("long line", eds_long_line(&eds, extra)),
    ] {
        g.throughput(Throughput::Bytes(t.len() as u64));
        g.bench_function(format!("eds {layout} {} bytes", t.len()), |b| {
            b.iter(|| od::eds::read_file(t.as_bytes(), "bench.eds").expect("generated EDS reads"))
        });
    }
    g.finish();
}

criterion_group!(benches, layout);
criterion_main!(benches);
