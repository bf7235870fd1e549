#![no_main]
//! Arbitrary frames, with time passing between them, into an SDO server on a small dictionary: no panic,
//! no unbounded allocation (libFuzzer's -rss_limit_mb and -malloc_limit_mb catch those), and every frame
//! the server sends parses as a server frame or is a block segment.

use std::time::{Duration, Instant};

use od::sdo::server::{SdoServer, ServerConfig};
use od::{AccessType, DataType, Dictionary, Object, ObjectKind, SubObject, Value};

fn dictionary() -> Dictionary {
    let mut d = Dictionary::new();
    d.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro),
    ));
    d.insert(Object::var(
        0x1017,
        SubObject::new("Heartbeat", DataType::Unsigned16, AccessType::Rw),
    ));
    d.insert(Object::var(
        0x1008,
        SubObject::new("Name", DataType::VisibleString, AccessType::Rw)
            .with_bit_size(8 * 64)
            .with_default(Value::String("a name that needs a segmented upload".into())),
    ));
    d.insert(Object::var(
        0x2000,
        SubObject::new("Blob", DataType::Domain, AccessType::Rw),
    ));
    d.insert(
        Object::structured(0x2001, "Rec", ObjectKind::Record)
            .with_sub(
                0,
                SubObject::new("n", DataType::Unsigned8, AccessType::Ro)
                    .with_default(Value::Uint(2)),
            )
            .with_sub(
                1,
                SubObject::new("lim", DataType::Integer32, AccessType::Rw)
                    .with_limits(Some(Value::Int(-10)), Some(Value::Int(10))),
            )
            .with_sub(2, SubObject::new("wo", DataType::Unsigned8, AccessType::Wo)),
    );
    d
}

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let mut d = dictionary();
    let config = ServerConfig {
        domain_limit: 4096,
        ..ServerConfig::default()
    };
    let mut server = SdoServer::new(config);
    let mut now = Instant::now();
    // Each record: one byte of time step (in 10 ms), eight bytes of frame.
    for chunk in data.chunks_exact(9) {
        now += Duration::from_millis(chunk[0] as u64 * 10);
        if server.poll_timeout().is_some_and(|t| t <= now) {
            server.handle_timeout(now);
        }
        let frame: [u8; 8] = chunk[1..9].try_into().unwrap();
        server.handle_frame(now, &frame, &mut d);
        let mut sent = 0;
        while let Some(f) = server.poll_transmit() {
            sent += 1;
            assert!(sent <= 128, "a block is at most 127 segments");
            let _ = od::sdo::ServerFrame::parse(&f);
        }
        while server.poll_event().is_some() {}
    }
});
