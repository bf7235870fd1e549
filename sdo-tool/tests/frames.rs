//! The frames `sdo-tool` puts on the bus, byte for byte, as worked out from CiA 301: a read of 4
//! bytes is one expedited upload (§7.2.4.3.3, request 0x40, answer 0x43), with or without a
//! description; block transfer only for what is large or when asked.

mod common;
mod x67;

use std::time::Duration;

use socketcan_node::transport::{BusEvent, CanBus, SocketcandClient};
use x67::{eds, Running};

/// Every frame `tap` holds, as `COB#DATA` in candump's notation (upper-case hex).
fn frames(tap: &mut socketcan_node::transport::Endpoint) -> Vec<String> {
    std::iter::from_fn(|| tap.try_recv())
        .map(|f| text(&f))
        .collect()
}

fn text(f: &sdo_tool::link::CanFrame) -> String {
    let data: String = f.data().iter().map(|b| format!("{b:02X}")).collect();
    format!("{:03X}#{data}", f.raw_id())
}

/// What `tap` (a socketcand client) receives until `quiet` passes without a frame.
fn frames_until_quiet(tap: &mut SocketcandClient, quiet: Duration) -> Vec<String> {
    let mut out = Vec::new();
    while let Ok(Some(event)) = tap.recv(quiet) {
        if let BusEvent::Frame { frame, .. } = event {
            out.push(text(&frame));
        }
    }
    out
}

/// `read 5 0x1018:01 u32`, and with `--od` the same entry by address and by its name: each is the
/// request `605#4018100100000000` (upload 0x1018:01) and the answer `585#43181001 2E0B0000`
/// (expedited, 4 bytes: vendor 0x00000B2E), nothing else — no identity read before it, no block
/// transfer.
#[test]
fn a_four_byte_read_is_one_expedited_request_and_its_answer() {
    let n = Running::start();
    let od = eds();
    let mut tap = n.bus.endpoint();
    let exact = vec![
        "605#4018100100000000".to_string(),
        "585#431810012E0B0000".to_string(),
    ];
    for (argv, shown) in [
        (&["read", "5", "0x1018:01", "u32"][..], "2862\n"),
        (&["--od", &od, "read", "5", "0x1018:01"], "0x00000B2E\n"),
        (&["--od", &od, "read", "5", "Vendor-ID"], "0x00000B2E\n"),
    ] {
        frames(&mut tap);
        assert_eq!(n.tool(argv).unwrap(), shown, "{argv:?}");
        assert_eq!(frames(&mut tap), exact, "{argv:?}");
    }
    // Node-IDs are 1 to 127: 0 and 128 are refused (exit 2) with nothing sent.
    for node in ["0", "128"] {
        let e = n.tool(&["read", node, "0x1018:01", "u32"]).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert_eq!(e.to_string(), format!("node {node} is not 1 to 127"));
    }
    assert_eq!(frames(&mut tap), Vec::<String>::new());
}

/// `--block` asks for block upload of what may be larger than 4 bytes (`605#A4081000 7F000000`:
/// 127 segments a sub-block, CRC, no protocol switch), the default segmented upload
/// (`605#40081000…`, answered `585#41081000 18000000`: 24 bytes announced); a 4-byte value stays
/// expedited with `--block` too.
#[test]
fn block_transfer_when_asked() {
    let n = Running::start();
    let mut tap = n.bus.endpoint();
    let name = "\"X67BC4321-10 / X67SM2436\"\n";
    assert_eq!(n.tool(&["read", "5", "0x1008:00", "vs"]).unwrap(), name);
    let f = frames(&mut tap);
    assert_eq!(f[..2], ["605#4008100000000000", "585#4108100018000000"]);
    // 24 bytes in 4 segments of 7, each asked for and answered.
    assert_eq!(f.len(), 2 + 4 * 2);
    assert_eq!(
        n.tool(&["--block", "read", "5", "0x1008:00", "vs"])
            .unwrap(),
        name
    );
    let f = frames(&mut tap);
    assert_eq!(f[..2], ["605#A40810007F000000", "585#C608100018000000"]);
    assert_eq!(
        n.tool(&["--block", "read", "5", "0x1018:01", "u32"])
            .unwrap(),
        "2862\n"
    );
    assert_eq!(
        frames(&mut tap),
        ["605#4018100100000000", "585#431810012E0B0000"]
    );
    let e = n
        .tool(&["--block", "--no-block", "read", "5", "0x1018:01", "u32"])
        .unwrap_err();
    assert_eq!(e.exit_code(), 2);
}

/// Against `canopen-node` running `examples/io-device.eds` (vendor 0xABC, product 0x401; 0x2000:01
/// "Program 1" a DOMAIN): with the description, a write of 65 bytes is a block download
/// (`603#C6002001 41000000`: CRC, size 65), one of 64 bytes segmented (`603#21002001 40000000`);
/// a read of the DOMAIN is a block upload offering the switch to a normal upload up to 64 bytes
/// (`603#A4002001 7F400000`), which the node takes for its 3 bytes: the expedited answer
/// `583#47002001 01020300` (CiA 301 §7.2.4.3.13).
#[test]
fn a_domain_goes_by_block_transfer() {
    let od = testkit::root().join("examples/io-device.eds");
    let od = od.to_str().unwrap();
    let (_node, port) = common::node_server(&["--od", &format!("{od}@3")]);
    let bus = common::socketcand_bus(port);
    let mut tap = SocketcandClient::connect("127.0.0.1", port, "can0").unwrap();
    let global = ["--bus", bus.as_str(), "--od", od];
    let quiet = Duration::from_millis(300);
    frames_until_quiet(&mut tap, quiet);
    let bytes = |n: usize| {
        (0..n)
            .map(|k| format!("{:02X}", k as u8))
            .collect::<String>()
    };
    // A write looks at the node's identity first (0x1018:01 and :02, expedited), then writes.
    let identity = [
        "603#4018100100000000",
        "583#43181001BC0A0000",
        "603#4018100200000000",
        "583#4318100201040000",
    ];
    common::sdo_tool_ok(&global, &["write", "3", "0x2000:01", &bytes(65)]);
    let f = frames_until_quiet(&mut tap, quiet);
    assert_eq!(f[..4], identity);
    assert_eq!(f[4], "603#C600200141000000", "{f:?}");
    common::sdo_tool_ok(&global, &["write", "3", "0x2000:01", &bytes(64)]);
    let f = frames_until_quiet(&mut tap, quiet);
    assert_eq!(f[4], "603#2100200140000000", "{f:?}");
    common::sdo_tool_ok(&global, &["write", "3", "0x2000:01", "01 02 03"]);
    frames_until_quiet(&mut tap, quiet);
    assert_eq!(
        common::sdo_tool_ok(&global, &["read", "3", "0x2000:01"]),
        "01 02 03\n"
    );
    let f = frames_until_quiet(&mut tap, quiet);
    assert_eq!(f, ["603#A40020017F400000", "583#4700200101020300"]);
}

/// A description of several devices (an `EtherCATInfoList` of the SMD23K-B/SMD24K ESI, an
/// X67SM2437 of the X67's vendor whose 0x2130 is named `Other03aRead`, and the X67 ESI): the node's
/// identity, read first (`605#40181001…`, `605#40181002…`, expedited), picks its device by vendor
/// and product, the fourth of the file, whose name `ConfigOutput03aRead` the read then takes, and
/// whose records it reads whole (0x1800, which the SMD's ESI does not have).
#[test]
fn the_identity_picks_the_device_of_a_description_of_several() {
    let n = Running::start();
    let root = testkit::root();
    let esi = |path: &str| {
        let text = std::fs::read_to_string(root.join(path)).unwrap();
        let start = text.find("<EtherCATInfo").unwrap();
        text[start..].to_string()
    };
    let other = esi("fixtures/x67/X67SM2436.esi.xml")
        .replace("ProductCode=\"#x00002436\"", "ProductCode=\"#x00002437\"")
        .replace(
            "<Name>ConfigOutput03aRead</Name>",
            "<Name>Other03aRead</Name>",
        );
    let list = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<EtherCATInfoList>\n{}\n{other}\n{}\n</EtherCATInfoList>\n",
        esi("fixtures/smd/SMD23K-B_SMD24K.esi.xml"),
        esi("fixtures/x67/X67SM2436.esi.xml")
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bus.xml");
    std::fs::write(&path, list).unwrap();
    let od = path.to_str().unwrap();
    let mut tap = n.bus.endpoint();
    assert_eq!(
        n.tool(&["--od", od, "read", "5", "ConfigOutput03aRead"])
            .unwrap(),
        "0\n"
    );
    assert_eq!(
        frames(&mut tap),
        [
            "605#4018100100000000",
            "585#431810012E0B0000",
            "605#4018100200000000",
            "585#4318100236240000",
            "605#4030210000000000",
            "585#4F30210000000000",
        ]
    );
    let record = n.tool(&["--od", od, "read", "5", "0x1800"]).unwrap();
    assert!(
        record.starts_with("0x1800:00  ")
            && record.contains("\n0x1800:01  ")
            && record.contains(" = 0x00000185\n"),
        "{record}"
    );
}

/// A description without an identity (vendor and product 0) is not checked against the node: a
/// write is the write alone (`605#2F102100 14…`, ConfigOutput03a = 20). One with a vendor but no
/// product is: the identity is read before the write.
#[test]
fn a_description_without_identity_is_not_checked() {
    let n = Running::start();
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(eds()).unwrap();
    let mut tap = n.bus.endpoint();
    let write = |od: &str, tap: &mut socketcan_node::transport::Endpoint| {
        frames(tap);
        assert_eq!(
            n.tool(&["--od", od, "write", "5", "ConfigOutput03a", "20"])
                .unwrap(),
            "OK\n"
        );
        frames(tap)
    };
    let none = dir.path().join("none.eds");
    std::fs::write(
        &none,
        text.replace("VendorNumber=0x00000B2E", "VendorNumber=0x00000000")
            .replace("ProductNumber=0x00002436", "ProductNumber=0x00000000"),
    )
    .unwrap();
    assert_eq!(
        write(none.to_str().unwrap(), &mut tap),
        ["605#2F10210014000000", "585#6010210000000000"]
    );
    let vendor = dir.path().join("vendor.eds");
    std::fs::write(
        &vendor,
        text.replace("ProductNumber=0x00002436", "ProductNumber=0x00000000"),
    )
    .unwrap();
    let f = write(vendor.to_str().unwrap(), &mut tap);
    assert_eq!(f.len(), 6, "{f:?}");
    assert_eq!(f[0], "605#4018100100000000");
    assert_eq!(f[2], "605#4018100200000000");
}

/// `send` puts cansend's frame on the bus as written: an 11-bit data frame, a remote frame, a
/// 29-bit one, bytes with dots; a frame that is none is refused (exit 2) with nothing sent.
#[test]
fn send_puts_the_frame_on_the_bus() {
    let n = Running::start();
    let mut tap = n.bus.endpoint();
    let sent = |tap: &mut socketcan_node::transport::Endpoint| -> Vec<String> {
        std::iter::from_fn(|| tap.try_recv())
            .filter(|f| f.raw_id() != 0x585)
            .map(|f| f.to_string())
            .collect()
    };
    for (argv, frame) in [
        ("123#DEADBEEF", "123#DEADBEEF"),
        ("123#R", "123#R0"),
        ("12345678#0102", "12345678#0102"),
        ("5A1#11.2233.44", "5A1#11223344"),
        ("7FF#", "7FF#"),
    ] {
        assert_eq!(n.tool(&["send", argv]).unwrap(), "");
        assert_eq!(sent(&mut tap), [frame], "{argv}");
    }
    let json = n.tool(&["--json", "send", "181#01"]).unwrap();
    assert_eq!(json, "{\"sent\":\"181#01\"}\n");
    sent(&mut tap);
    for bad in [
        "800#00",
        "123#1",
        "123#001122334455667788",
        "1234#00",
        "123",
    ] {
        let e = n.tool(&["send", bad]).unwrap_err();
        assert_eq!(e.exit_code(), 2, "{bad}");
        assert!(
            e.to_string().starts_with(&format!("frame \"{bad}\": ")),
            "{e}"
        );
    }
    assert_eq!(sent(&mut tap), Vec::<String>::new());
}

/// `sync`: one SYNC without data on 0x080; three with the counter 1, 2, 3, 20 ms apart (at least
/// 40 ms from the first to the last); the counter back to 1 after the overflow value; another
/// COB-ID.
#[test]
fn sync_produces_sync_messages() {
    let n = Running::start();
    let mut tap = n.bus.endpoint();
    let syncs = |tap: &mut socketcan_node::transport::Endpoint, cob: u32| -> Vec<String> {
        std::iter::from_fn(|| tap.try_recv())
            .filter(|f| f.raw_id() == cob)
            .map(|f| f.to_string())
            .collect()
    };
    assert_eq!(n.tool(&["sync"]).unwrap(), "1 SYNC sent on 0x080\n");
    assert_eq!(syncs(&mut tap, 0x80), ["080#"]);
    let t0 = std::time::Instant::now();
    let out = n
        .tool(&["sync", "--count", "3", "--period-ms", "20", "--counter"])
        .unwrap();
    assert!(t0.elapsed() >= Duration::from_millis(40));
    assert_eq!(out, "3 SYNC sent on 0x080\n");
    assert_eq!(syncs(&mut tap, 0x80), ["080#01", "080#02", "080#03"]);
    let out = n
        .tool(&[
            "sync",
            "--count",
            "5",
            "--period-ms",
            "0",
            "--counter",
            "--overflow",
            "2",
            "--cob-id",
            "0x90",
        ])
        .unwrap();
    assert_eq!(out, "5 SYNC sent on 0x090\n");
    assert_eq!(
        syncs(&mut tap, 0x90),
        ["090#01", "090#02", "090#01", "090#02", "090#01"]
    );
    for bad in [
        &["sync", "--cob-id", "0x800"][..],
        &["sync", "--overflow", "3"],
        &["sync", "--counter", "--overflow", "241"],
    ] {
        assert_eq!(n.tool(bad).unwrap_err().exit_code(), 2, "{bad:?}");
    }
}

/// `sync --count 0` sends until Ctrl-C, then says how many and exits 0; between two messages it
/// sleeps: a second of SYNC every 100 ms takes far less than a second of CPU time (the shell's
/// `times` of its child).
#[test]
fn sync_until_ctrl_c_and_asleep_between() {
    use std::process::{Command, Stdio};
    let (mut node, port) = x67::hub(3);
    let bus = common::socketcand_bus(port);
    let tool = env!("CARGO_BIN_EXE_sdo-tool");
    let child = Command::new(tool)
        .args(["--bus", &bus, "sync", "--count", "0", "--period-ms", "20"])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(500));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    let line = String::from_utf8_lossy(&out.stdout);
    let sent: u64 = line.split(' ').next().unwrap().parse().unwrap();
    assert!(
        sent >= 2 && line.ends_with(" SYNC sent on 0x080\n"),
        "{line}"
    );
    let script = format!("{tool} --bus {bus} sync --count 11 --period-ms 100 >/dev/null; times");
    let out = Command::new("bash").args(["-c", &script]).output().unwrap();
    let times = String::from_utf8_lossy(&out.stdout);
    // The second line: the children's user and system time, `0m0.012s 0m0.004s`.
    let child_line = times.lines().nth(1).unwrap();
    let seconds: f64 = child_line
        .split(' ')
        .map(|t| {
            let (m, s) = t.trim_end_matches('s').split_once('m').unwrap();
            m.parse::<f64>().unwrap() * 60.0 + s.parse::<f64>().unwrap()
        })
        .sum();
    assert!(
        seconds < 0.5,
        "{seconds} s of CPU for a second of SYNC: {times}"
    );
    node.kill().unwrap();
    node.wait().unwrap();
}
