//! SDO throughput in-process: a 1 MiB DOMAIN downloaded and uploaded between a client and a server with
//! no channel delay, segmented and block. Criterion reports frames per second (both directions counted);
//! MB/s is 1 MiB divided by the time (`cargo bench -p od --bench sdo`).

use std::time::Instant;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use od::sdo::client::{ClientConfig, ClientEvent, SdoClient};
use od::sdo::server::{SdoServer, ServerConfig};
use od::sdo::Address;
use od::{AccessType, DataType, Dictionary, Object, SubObject};

const MIB: usize = 1 << 20;
const DOMAIN: Address = Address::new(0x2000, 0);

fn dictionary() -> Dictionary {
    let mut d = Dictionary::new();
    d.insert(Object::var(
        0x2000,
        SubObject::new("Blob", DataType::Domain, AccessType::Rw),
    ));
    d
}

/// Runs one transfer to its end; answers the number of frames both sides sent.
fn run(client: &mut SdoClient, server: &mut SdoServer, d: &mut Dictionary, now: Instant) -> u64 {
    let mut frames = 0;
    loop {
        let mut moved = false;
        while let Some(f) = client.poll_transmit() {
            frames += 1;
            moved = true;
            server.handle_frame(now, &f, d);
        }
        while let Some(f) = server.poll_transmit() {
            frames += 1;
            moved = true;
            client.handle_frame(now, &f);
        }
        while server.poll_event().is_some() {}
        while let Some(e) = client.poll_event() {
            match e {
                ClientEvent::Downloaded
                | ClientEvent::Uploaded(_)
                | ClientEvent::UploadedToSink { .. } => return frames,
                ClientEvent::Failed(e) => panic!("{e}"),
                ClientEvent::Progress { .. } => {}
                other => panic!("unexpected {other:?}"),
            }
        }
        assert!(moved, "stalled");
    }
}

fn sdo(c: &mut Criterion) {
    let data: Vec<u8> = (0..MIB).map(|i| (i * 7) as u8).collect();
    let server_config = ServerConfig {
        domain_limit: 2 * MIB,
        ..ServerConfig::default()
    };
    let mut g = c.benchmark_group("sdo 1 MiB");
    g.sample_size(10);
    for (name, config) in [
        (
            "segmented",
            ClientConfig {
                block: false,
                ..ClientConfig::default()
            },
        ),
        ("block", ClientConfig::default()),
    ] {
        let now = Instant::now();
        // Count the frames of each direction once, for the throughput.
        let mut d = dictionary();
        let mut client = SdoClient::new(config.clone());
        let mut server = SdoServer::new(server_config);
        client.start_download(now, DOMAIN, data.clone()).unwrap();
        let down = run(&mut client, &mut server, &mut d, now);
        client.start_upload(now, DOMAIN).unwrap();
        let up = run(&mut client, &mut server, &mut d, now);

        g.throughput(Throughput::Elements(down));
        g.bench_function(format!("download {name} ({down} frames)"), |b| {
            b.iter(|| {
                client.start_download(now, DOMAIN, data.clone()).unwrap();
                run(&mut client, &mut server, &mut d, now)
            })
        });
        g.throughput(Throughput::Elements(up));
        g.bench_function(format!("upload {name} ({up} frames)"), |b| {
            b.iter(|| {
                client.start_upload(now, DOMAIN).unwrap();
                run(&mut client, &mut server, &mut d, now)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, sdo);
criterion_main!(benches);
