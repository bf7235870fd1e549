//! The network manager against scripted slaves: every frame it sends, byte for byte, worked out
//! from CiA 301 and CiA 302-2, and every failure's letter and words.

use std::time::{Duration, Instant};

use can_link::CanFrame;
use canopen_net::boot::{
    BootEvent, ConfigEntry, ErrorStatus, Expect, Manager, ManagerConfig, NodeState, Plan, SlavePlan,
};
use canopen_net::concise::Entry;

fn expect(value: u32, origin: &str) -> Expect {
    Expect {
        value,
        origin: origin.into(),
    }
}

/// Node 2: device type 0x00020192, vendor 0x360, product 7 checked; one entry (0x1017 = 100 ms);
/// the master consumes its heartbeat with 300 ms; boot + mandatory.
fn slave() -> SlavePlan {
    SlavePlan {
        node_id: 2,
        name: "drive".into(),
        assignment: 0x0000_000D,
        device_type: expect(0x0002_0192, "bus.yml:9, drive.eds"),
        identity: [
            expect(0x360, "bus.yml:9, drive.eds"),
            expect(7, "bus.yml:9, drive.eds"),
            expect(0, ""),
            expect(0, ""),
        ],
        software: expect(0, ""),
        heartbeat_ms: 300,
        heartbeat_origin: "bus.yml:8 drive.heartbeat_producer".into(),
        configuration: vec![ConfigEntry {
            entry: Entry::new(0x1017, 0, vec![100, 0]),
            origin: "bus.yml:10 drive.heartbeat_producer".into(),
        }],
        stamp: None,
    }
}

fn plan(slaves: Vec<SlavePlan>, startup: u32) -> Plan {
    Plan {
        master_id: 1,
        startup,
        boot_time_ms: 0,
        heartbeat_ms: 0,
        slaves,
    }
}

struct Bus {
    m: Manager,
    now: Instant,
    events: Vec<BootEvent>,
}

impl Bus {
    fn new(plan: Plan) -> Bus {
        let config = ManagerConfig {
            sdo_timeout: Duration::from_millis(100),
            boot_up_wait: Duration::from_millis(500),
            retry: Duration::from_secs(1),
        };
        Bus {
            m: Manager::new(plan, config),
            now: Instant::now(),
            events: Vec::new(),
        }
    }

    /// Every frame sent since the last call, as `COB#HEX`.
    fn sent(&mut self) -> Vec<String> {
        let mut v = Vec::new();
        while let Some(f) = self.m.poll_transmit() {
            v.push(text(&f));
        }
        while let Some(e) = self.m.poll_event() {
            self.events.push(e);
        }
        v
    }

    fn feed(&mut self, cob: u16, data: &[u8]) {
        self.m
            .handle_frame(self.now, &CanFrame::new(cob, data).unwrap());
    }

    /// Runs the time on by `d`, calling the manager at each instant it asked for on the way.
    fn advance(&mut self, d: Duration) {
        let end = self.now + d;
        let mut calls = 0;
        while let Some(t) = self.m.poll_timeout().filter(|&t| t <= end) {
            self.now = self.now.max(t);
            self.m.handle_timeout(self.now);
            calls += 1;
            assert!(
                calls < 100_000,
                "the manager asks for a call at {t:?} again and again"
            );
        }
        self.now = end;
        self.m.handle_timeout(self.now);
    }

    fn states(&mut self, node: u8) -> Vec<String> {
        self.sent();
        self.events
            .iter()
            .filter_map(|e| match e {
                BootEvent::Node { node: n, state } if *n == node => Some(state.word()),
                _ => None,
            })
            .collect()
    }

    fn error(&self, node: u8) -> String {
        let r = self.m.nodes().find(|r| r.node == node).unwrap();
        r.last_error
            .as_ref()
            .map(|e| e.to_string())
            .unwrap_or_default()
    }
}

fn text(f: &CanFrame) -> String {
    let hex: String = f.data().iter().map(|b| format!("{b:02X}")).collect();
    format!("{:03X}#{hex}", f.raw_id())
}

/// Answers the identity check of node 2 with `vendor` and `product`.
fn identity(bus: &mut Bus, vendor: u32, product: u32) {
    bus.feed(0x702, &[0x00]);
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
    bus.feed(0x582, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]);
    assert_eq!(bus.sent(), ["602#4018100100000000"]);
    let v = vendor.to_le_bytes();
    bus.feed(0x582, &[0x43, 0x18, 0x10, 0x01, v[0], v[1], v[2], v[3]]);
    if vendor != 0x360 {
        return;
    }
    assert_eq!(bus.sent(), ["602#4018100200000000"]);
    let p = product.to_le_bytes();
    bus.feed(0x582, &[0x43, 0x18, 0x10, 0x02, p[0], p[1], p[2], p[3]]);
}

#[test]
fn a_slave_boots_checked_configured_and_started_frame_by_frame() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    assert_eq!(
        bus.sent(),
        ["000#8200"],
        "NMT reset communication, all nodes"
    );
    identity(&mut bus, 0x360, 7);
    // 0x1017:00 = 100, expedited download of 2 bytes (ccs 1, n 2, e, s: 0x2B).
    assert_eq!(bus.sent(), ["602#2B17100064000000"]);
    bus.feed(0x582, &[0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0]);
    assert_eq!(bus.sent(), Vec::<String>::new(), "waits for a heartbeat");
    bus.advance(Duration::from_millis(100));
    bus.feed(0x702, &[0x7F]);
    assert_eq!(bus.sent(), ["000#0102"], "NMT start remote node 2");
    // Its state before the first event: reset.
    assert_eq!(bus.states(2), ["checking", "config 0/1", "heartbeat", "up"]);
    assert!(bus.events.contains(&BootEvent::NetworkUp));
    assert!(bus.m.network_up());
    let r = bus.m.nodes().next().unwrap();
    assert_eq!(
        r.identity,
        [Some(0x0002_0192), Some(0x360), Some(7), None, None]
    );
    assert_eq!(r.configured, (1, 1));
    assert_eq!(r.boots, 1);
}

#[test]
fn a_different_vendor_ends_with_d_naming_both_values_and_the_origin() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    identity(&mut bus, 0x9A, 7);
    assert_eq!(
        bus.sent(),
        Vec::<String>::new(),
        "nothing written, nothing started"
    );
    assert_eq!(
        bus.error(2),
        "node 2 [D] vendor-ID 0x00000360 expected (bus.yml:9, drive.eds), 0x0000009A found in \
         0x1018:01 — a device of another vendor answers at this node-ID"
    );
    assert!(!bus.m.network_up());
    // No retry without a boot-up message: asking again cannot change the device.
    bus.advance(Duration::from_secs(5));
    assert_eq!(bus.sent(), Vec::<String>::new());
    assert!(bus.m.settled());
}

#[test]
fn a_different_device_type_or_product_have_their_own_letters() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    bus.feed(0x702, &[0x00]);
    bus.sent();
    bus.feed(0x582, &[0x43, 0x00, 0x10, 0x00, 0x91, 0x01, 0x02, 0x00]);
    assert_eq!(
        bus.error(2),
        "node 2 [C] device type 0x00020192 expected (bus.yml:9, drive.eds), 0x00020191 found in \
         0x1000:00 — a different kind of device answers at this node-ID"
    );
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    identity(&mut bus, 0x360, 8);
    assert_eq!(
        bus.error(2),
        "node 2 [M] product code 0x00000007 expected (bus.yml:9, drive.eds), 0x00000008 found in \
         0x1018:02 — another product answers at this node-ID"
    );
}

#[test]
fn a_missing_node_ends_with_b_and_is_asked_again_every_retry() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    assert_eq!(bus.sent(), ["000#8200"]);
    // No boot-up: after the 500 ms wait the boot starts anyway.
    bus.advance(Duration::from_millis(499));
    assert_eq!(bus.sent(), Vec::<String>::new());
    bus.advance(Duration::from_millis(1));
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
    // 100 ms without an answer: the client aborts with 0x05040000 (SDO protocol timed out).
    bus.advance(Duration::from_millis(100));
    assert_eq!(bus.sent(), ["602#8000100000000405"]);
    assert_eq!(
        bus.error(2),
        "node 2 [B] device type 0x1000:00 could not be read: no answer within 100 ms — no node \
         answers at this node-ID"
    );
    // Asked again one second later, and again.
    bus.advance(Duration::from_millis(999));
    assert_eq!(bus.sent(), Vec::<String>::new());
    bus.advance(Duration::from_millis(1));
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
    bus.advance(Duration::from_millis(1100));
    assert_eq!(bus.sent(), ["602#8000100000000405", "602#4000100000000000"]);
    assert_eq!(bus.m.missing(), [2]);
    assert!(!bus.m.settled(), "tried again in a second");
}

#[test]
fn a_refused_configuration_write_ends_with_j_naming_the_entry_and_its_line() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    identity(&mut bus, 0x360, 7);
    assert_eq!(bus.sent(), ["602#2B17100064000000"]);
    // Abort 0x06090030 (invalid value).
    bus.feed(0x582, &[0x80, 0x17, 0x10, 0x00, 0x30, 0x00, 0x09, 0x06]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    assert_eq!(
        bus.error(2),
        "node 2 [J] writing 0x1017:00 = 0x64 (bus.yml:10 drive.heartbeat_producer) failed: the \
         node refused it with 0x06090030 (Invalid value for parameter (download only)) — the node \
         refuses its configuration"
    );
    assert_eq!(bus.states(2).last().map(String::as_str), Some("failed J"));
    // A boot-up message boots it again from the start.
    bus.feed(0x702, &[0x00]);
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
}

/// Starts the manager and takes node 2 through its checks and its one entry, up to the wait for
/// its heartbeat.
fn configured(bus: &mut Bus) {
    bus.m.start(bus.now);
    bus.sent();
    identity(bus, 0x360, 7);
    bus.sent();
    bus.feed(0x582, &[0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0]);
}

/// Boots node 2 to Up.
fn boot(bus: &mut Bus) {
    configured(bus);
    bus.feed(0x702, &[0x7F]);
    bus.sent();
    assert!(bus.m.network_up());
}

#[test]
fn no_heartbeat_after_configuration_ends_with_k() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    configured(&mut bus);
    bus.advance(Duration::from_millis(299));
    assert_eq!(bus.states(2).last().map(String::as_str), Some("heartbeat"));
    bus.advance(Duration::from_millis(1));
    assert_eq!(
        bus.error(2),
        "node 2 [K] no heartbeat within 300 ms of its configuration (consumer time, bus.yml:8 \
         drive.heartbeat_producer) — its heartbeat producer 0x1017 is 0 or slower than that"
    );
    assert_eq!(bus.sent(), Vec::<String>::new(), "not started");
}

#[test]
fn a_lost_heartbeat_is_e_and_the_node_is_booted_again_when_it_returns() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    boot(&mut bus);
    // Heartbeats within 300 ms keep it up.
    for _ in 0..5 {
        bus.advance(Duration::from_millis(250));
        bus.feed(0x702, &[0x05]);
    }
    assert_eq!(bus.states(2).last().map(String::as_str), Some("up"));
    bus.advance(Duration::from_millis(299));
    assert_eq!(bus.states(2).last().map(String::as_str), Some("up"));
    bus.advance(Duration::from_millis(1));
    assert_eq!(bus.states(2).last().map(String::as_str), Some("failed E"));
    assert_eq!(
        bus.error(2),
        "node 2 [E] heartbeat lost: none for 300 ms (consumer time, bus.yml:8 \
         drive.heartbeat_producer) — the node stopped, lost power or left the bus"
    );
    // Its heartbeat back: the boot starts again.
    bus.feed(0x702, &[0x05]);
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
}

#[test]
fn a_boot_up_message_of_a_running_node_starts_its_boot_again() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    boot(&mut bus);
    bus.feed(0x702, &[0x00]);
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
    assert_eq!(bus.states(2).last().map(String::as_str), Some("checking"));
}

#[test]
fn start_all_nodes_sends_one_command_once_every_slave_booted() {
    // 0x1F80 = 0x03: NMT master, start all nodes at once.
    let mut bus = Bus::new(plan(vec![slave()], 0x03));
    configured(&mut bus);
    bus.feed(0x702, &[0x7F]);
    assert_eq!(bus.sent(), ["000#0100"], "NMT start, all nodes");
    // 0x1F80 = 0x09: the master starts no slave.
    let mut bus = Bus::new(plan(vec![slave()], 0x09));
    configured(&mut bus);
    bus.feed(0x702, &[0x7F]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    assert!(bus.m.network_up());
}

#[test]
fn the_boot_time_passing_without_a_mandatory_slave_is_reported_once() {
    let mut p = plan(vec![slave()], 0x01);
    p.boot_time_ms = 2000;
    let mut bus = Bus::new(p);
    bus.m.start(bus.now);
    bus.advance(Duration::from_millis(1999));
    bus.sent();
    assert!(!bus
        .events
        .iter()
        .any(|e| matches!(e, BootEvent::BootTimeout { .. })));
    bus.advance(Duration::from_millis(1));
    bus.advance(Duration::from_secs(3));
    bus.sent();
    let timeouts: Vec<_> = bus
        .events
        .iter()
        .filter(|e| matches!(e, BootEvent::BootTimeout { .. }))
        .collect();
    assert_eq!(timeouts, [&BootEvent::BootTimeout { missing: vec![2] }]);
}

#[test]
fn a_kept_alive_operational_slave_is_not_reset_nor_booted_again() {
    let mut s = slave();
    s.assignment |= 0x10;
    let mut other = slave();
    other.node_id = 3;
    let mut bus = Bus::new(plan(vec![s, other], 0x01));
    bus.m.start(bus.now);
    assert_eq!(bus.sent(), ["000#8203"], "only node 3 is reset");
    bus.feed(0x702, &[0x05]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    let r = bus.m.nodes().next().unwrap();
    assert_eq!((r.state.clone(), r.kept), (NodeState::Up, true));
}

#[test]
fn the_master_beats_pre_operational_until_the_network_is_up() {
    let mut p = plan(vec![slave()], 0x01);
    p.heartbeat_ms = 100;
    let mut bus = Bus::new(p);
    bus.m.start(bus.now);
    assert_eq!(bus.sent(), ["000#8200", "701#7F"]);
    bus.advance(Duration::from_millis(99));
    assert_eq!(bus.sent(), Vec::<String>::new());
    bus.advance(Duration::from_millis(1));
    assert_eq!(bus.sent(), ["701#7F"]);
    identity(&mut bus, 0x360, 7);
    bus.sent();
    bus.feed(0x582, &[0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0]);
    bus.feed(0x702, &[0x7F]);
    assert_eq!(bus.sent(), ["000#0102"]);
    bus.advance(Duration::from_millis(100));
    assert_eq!(bus.sent(), ["701#05"]);
}

#[test]
fn an_emergency_is_reported_with_its_fields() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    bus.feed(0x082, &[0x10, 0x81, 0x11, 1, 2, 3, 4, 5]);
    bus.sent();
    assert!(bus.events.contains(&BootEvent::Emergency {
        node: 2,
        code: 0x8110,
        register: 0x11,
        data: [1, 2, 3, 4, 5]
    }));
    assert_eq!(ErrorStatus::J.letter(), 'J');
}

/// `examples/drive.eds` made the DCF of node 7: TPDO 1 its COB-ID as it is, event timer 50 ms,
/// mapping 0x6041 and 0x6064 (two entries); RPDO 1 its COB-ID 0x202 and one mapped entry without a
/// count; heartbeat 200 ms; a value for the statusword, which is read only; as `sdo-tool dump` or
/// a configuration tool writes one.
fn drive_dcf() -> canopen_net::boot::SlaveDcf {
    let eds = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/drive.eds");
    let mut text = std::fs::read_to_string(eds).unwrap();
    let set = |text: &mut String, section: &str, value: &str| {
        let head = format!("[{section}]");
        let at = text.find(&head).unwrap();
        let at = at + text[at..].find('\n').unwrap() + 1;
        text.insert_str(at, &format!("ParameterValue={value}\r\n"));
    };
    set(&mut text, "1010sub1", "0x65766173");
    set(&mut text, "1017", "200");
    set(&mut text, "1400sub1", "0x202");
    set(&mut text, "1401sub1", "$NODEID+0x300");
    set(&mut text, "1600sub1", "0x60400010");
    set(&mut text, "1800sub1", "$NODEID+0x180");
    set(&mut text, "1800sub5", "50");
    set(&mut text, "6041", "0x0237");
    text.push_str(
        "\r\n[1020]\r\nSubNumber=3\r\nParameterName=Verify configuration\r\nObjectType=0x8\r\n\
         \r\n[1020sub0]\r\nParameterName=Highest sub-index\r\nObjectType=0x7\r\n\
         DataType=0x0005\r\nAccessType=ro\r\nDefaultValue=2\r\n\
         \r\n[1020sub1]\r\nParameterName=Configuration date\r\nObjectType=0x7\r\n\
         DataType=0x0007\r\nAccessType=rw\r\nDefaultValue=0\r\nParameterValue=14000\r\n\
         \r\n[1020sub2]\r\nParameterName=Configuration time\r\nObjectType=0x7\r\n\
         DataType=0x0007\r\nAccessType=rw\r\nDefaultValue=0\r\nParameterValue=43200000\r\n",
    );
    set(&mut text, "1A00sub0", "2");
    set(&mut text, "1A00sub1", "0x60410010");
    set(&mut text, "1A00sub2", "0x60640020");
    text.push_str("\n[DeviceComissioning]\nNodeID=7\n");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("drive7.dcf");
    std::fs::write(&path, &text).unwrap();
    let (_, mut devices) = od::load::load(&path).unwrap();
    canopen_net::boot::SlaveDcf {
        name: "drive7".into(),
        file: "drive7.dcf".into(),
        desc: devices.swap_remove(0),
        text,
    }
}

#[test]
fn a_dcf_s_values_are_written_pdos_in_cia_301_order() {
    let plan = Plan::from_dcfs(&[drive_dcf()], 1).unwrap();
    let s = &plan.slaves[0];
    assert_eq!((s.node_id, s.assignment, s.heartbeat_ms), (7, 0x05, 600));
    assert_eq!(s.device_type.value, 0x0002_0192);
    let written: Vec<String> = s
        .configuration
        .iter()
        .map(|c| {
            let hex: String = c.entry.data.iter().map(|b| format!("{b:02X}")).collect();
            format!("{:04X}:{:02X}={hex}", c.entry.index, c.entry.sub)
        })
        .collect();
    // Not 0x1010 (a command, not configuration); 0x1017 first (index order); RPDO 1: its COB-ID 0x202 made invalid (bit 31), the mapping
    // emptied, its entry, its count (the entries', as the DCF gives none), the COB-ID valid; then
    // RPDO 2 with its COB-ID alone (0x307), made invalid and valid again; TPDO 1 alike with its
    // event timer. The statusword is not written.
    assert_eq!(
        written,
        [
            "1017:00=C800",
            "1400:01=02020080",
            "1600:00=00",
            "1600:01=10004060",
            "1600:00=01",
            "1400:01=02020000",
            "1401:01=07030080",
            "1401:01=07030000",
            "1800:01=87010080",
            "1800:05=3200",
            "1A00:00=00",
            "1A00:01=10004160",
            "1A00:02=20006460",
            "1A00:00=02",
            "1800:01=87010000",
            "1020:01=B0360000",
            "1020:02=002E9302",
        ]
    );
    // The stamp closes it: day 14000 since 1984, noon.
    assert_eq!(s.stamp, Some([14000, 43_200_000]));
    // Each entry names the line of its value.
    let origin = &s.configuration[0].origin;
    assert!(
        origin.starts_with("drive7.dcf:") && origin.ends_with(" 0x1017:00"),
        "{origin}"
    );
    let line: usize = origin["drive7.dcf:".len()..]
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let text = drive_dcf().text;
    assert_eq!(text.lines().nth(line - 1), Some("ParameterValue=200"));
    assert!(Plan::from_dcfs(&[drive_dcf(), drive_dcf()], 1)
        .unwrap_err()
        .starts_with("node-ID 7 is given twice"));
}

#[test]
fn the_configuration_s_progress_is_in_the_report_and_one_event() {
    let mut s = slave();
    s.configuration.push(ConfigEntry {
        entry: Entry::new(0x1800, 5, vec![50, 0]),
        origin: "bus.yml:20 drive.tpdo".into(),
    });
    let mut bus = Bus::new(plan(vec![s], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    identity(&mut bus, 0x360, 7);
    assert_eq!(bus.sent(), ["602#2B17100064000000"]);
    bus.feed(0x582, &[0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0]);
    assert_eq!(bus.sent(), ["602#2B00180532000000"]);
    let r = bus.m.nodes().next().unwrap();
    assert_eq!(
        (r.configured, r.state.word()),
        ((1, 2), "config 1/2".to_string())
    );
    assert_eq!(bus.states(2), ["checking", "config 0/2"]);
}

#[test]
fn frames_of_other_lengths_and_other_services_are_passed_over() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    bus.events.clear();
    // A heartbeat of two bytes, an SDO answer of seven, a SYNC (0x080) and an EMCY of seven bytes:
    // none is the frame it looks like.
    bus.feed(0x702, &[0x00, 0x00]);
    bus.feed(0x080, &[]);
    bus.feed(0x080, &[0; 8]);
    bus.feed(0x082, &[0x10, 0x81, 0x11, 1, 2, 3, 4]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    assert!(bus.events.is_empty(), "{:?}", bus.events);
    bus.feed(0x702, &[0x00]);
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
    bus.feed(0x582, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    // A heartbeat frame of eight bytes is no SDO answer either.
    bus.feed(0x702, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    assert_eq!(bus.states(2).last().map(String::as_str), Some("checking"));
}

#[test]
fn a_lost_mandatory_slave_resets_or_stops_every_node_as_0x1f80_says() {
    // 0x1F80 bit 4: reset all nodes, and the boot starts again.
    let mut bus = Bus::new(plan(vec![slave()], 0x11));
    boot(&mut bus);
    bus.advance(Duration::from_millis(300));
    assert_eq!(bus.sent(), ["000#8200"]);
    assert!(!bus.m.network_up());
    assert_eq!(bus.states(2).last().map(String::as_str), Some("reset"));
    // 0x1F80 bit 6: stop all nodes.
    let mut bus = Bus::new(plan(vec![slave()], 0x41));
    boot(&mut bus);
    bus.advance(Duration::from_millis(300));
    assert_eq!(bus.sent(), ["000#0200"]);
    // Neither: only that node is failed.
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    boot(&mut bus);
    bus.advance(Duration::from_millis(300));
    assert_eq!(bus.sent(), Vec::<String>::new());
    // An optional slave lost with bit 4 set: nothing for the others.
    let mut optional = slave();
    optional.assignment = 0x05;
    let mut bus = Bus::new(plan(vec![optional], 0x11));
    boot(&mut bus);
    bus.advance(Duration::from_millis(300));
    assert_eq!(bus.sent(), Vec::<String>::new());
}

#[test]
fn the_master_heartbeat_keeps_its_period_and_after_a_pause_starts_from_now() {
    let mut p = plan(vec![slave()], 0x01);
    p.heartbeat_ms = 100;
    let mut bus = Bus::new(p);
    let t0 = bus.now;
    bus.m.start(t0);
    bus.sent();
    let ms = |n| t0 + Duration::from_millis(n);
    let beats = |bus: &mut Bus| -> Vec<String> {
        bus.sent()
            .into_iter()
            .filter(|f| f.starts_with("701#"))
            .collect()
    };
    // The slave waits for its boot-up until 500 ms: the next call is the beat at 100 ms.
    assert_eq!(bus.m.poll_timeout(), Some(ms(100)));
    // Called 30 ms late: the beat goes, the next stays on the period (200 ms).
    bus.m.handle_timeout(ms(130));
    assert_eq!(beats(&mut bus), ["701#7F"]);
    assert_eq!(bus.m.poll_timeout(), Some(ms(200)));
    // Called exactly a period late: one beat, the next a period on, not at once.
    bus.m.handle_timeout(ms(300));
    assert_eq!(beats(&mut bus), ["701#7F"]);
    assert_eq!(bus.m.poll_timeout(), Some(ms(400)));
    // Called 50 ms late and then 250 ms late: one beat each, the last the next a period from now.
    bus.m.handle_timeout(ms(450));
    assert_eq!(beats(&mut bus), ["701#7F"]);
    assert_eq!(bus.m.poll_timeout(), Some(ms(500)));
    bus.m.handle_timeout(ms(750));
    assert_eq!(beats(&mut bus), ["701#7F"]);
    // (The slave's boot meanwhile asks for calls of its own.)
    bus.m.handle_timeout(ms(849));
    assert_eq!(beats(&mut bus), Vec::<String>::new());
    bus.m.handle_timeout(ms(850));
    assert_eq!(beats(&mut bus), ["701#7F"]);
}

#[test]
fn once_up_the_boot_time_no_longer_asks_for_a_call() {
    let mut s = slave();
    s.heartbeat_ms = 0;
    let mut p = plan(vec![s], 0x01);
    p.boot_time_ms = 2000;
    let mut bus = Bus::new(p);
    configured(&mut bus);
    assert_eq!(bus.sent(), ["000#0102"]);
    assert!(bus.m.network_up());
    assert_eq!(bus.m.poll_timeout(), None);
}

#[test]
fn start_all_waits_for_an_optional_slave_s_first_boot_to_end() {
    let mandatory = slave();
    let mut optional = slave();
    optional.node_id = 3;
    optional.assignment = 0x05;
    optional.identity = [expect(0, ""), expect(0, ""), expect(0, ""), expect(0, "")];
    optional.heartbeat_ms = 0;
    optional.configuration.clear();
    let mut bus = Bus::new(plan(vec![mandatory, optional], 0x03));
    bus.m.start(bus.now);
    bus.sent();
    bus.feed(0x703, &[0x00]);
    assert_eq!(bus.sent(), ["603#4000100000000000"]);
    // The mandatory one boots while the optional one is still being checked: no start yet.
    identity(&mut bus, 0x360, 7);
    bus.sent();
    bus.feed(0x582, &[0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0]);
    bus.feed(0x702, &[0x7F]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    assert!(!bus.m.network_up());
    // The optional one answers: its boot ends, every node starts with one command.
    bus.feed(0x583, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]);
    assert_eq!(bus.sent(), ["000#0100"]);
    assert!(bus.m.network_up());
}

#[test]
fn the_software_version_is_checked_when_0x1f81_bit_5_says_so() {
    let mut s = slave();
    s.identity = [expect(0, ""), expect(0, ""), expect(0, ""), expect(0, "")];
    s.software = expect(0x0001_0002, "bus.yml:12 drive.software_version");
    // Bit 5 clear: not read, the configuration follows 0x1000.
    let mut bus = Bus::new(plan(vec![s.clone()], 0x01));
    bus.m.start(bus.now);
    bus.feed(0x702, &[0x00]);
    bus.sent();
    bus.feed(0x582, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]);
    assert_eq!(bus.sent(), ["602#2B17100064000000"]);
    // Bit 5 set: 0x1F56:01 read; another value is H.
    s.assignment |= 0x20;
    let mut bus = Bus::new(plan(vec![s.clone()], 0x01));
    bus.m.start(bus.now);
    bus.feed(0x702, &[0x00]);
    bus.sent();
    bus.feed(0x582, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]);
    assert_eq!(bus.sent(), ["602#40561F0100000000"]);
    bus.feed(0x582, &[0x43, 0x56, 0x1F, 0x01, 0x01, 0x00, 0x01, 0x00]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    assert_eq!(
        bus.error(2),
        "node 2 [H] software identification 0x00010002 expected (bus.yml:12 \
         drive.software_version), 0x00010001 found in 0x1F56:01 — its software is to be updated, \
         which this manager does not do"
    );
    // The same value: on to the configuration. And 0 expected is not checked, bit 5 or not.
    let mut bus = Bus::new(plan(vec![s.clone()], 0x01));
    bus.m.start(bus.now);
    bus.feed(0x702, &[0x00]);
    bus.sent();
    bus.feed(0x582, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]);
    bus.sent();
    bus.feed(0x582, &[0x43, 0x56, 0x1F, 0x01, 0x02, 0x00, 0x01, 0x00]);
    assert_eq!(bus.sent(), ["602#2B17100064000000"]);
    s.software.value = 0;
    let mut bus = Bus::new(plan(vec![s], 0x01));
    bus.m.start(bus.now);
    bus.feed(0x702, &[0x00]);
    bus.sent();
    bus.feed(0x582, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]);
    assert_eq!(bus.sent(), ["602#2B17100064000000"]);
}

#[test]
fn only_a_silent_device_type_read_says_no_node_answers() {
    // The vendor-ID not answered: D, without the words of a missing node.
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    bus.feed(0x702, &[0x00]);
    bus.sent();
    bus.feed(0x582, &[0x43, 0x00, 0x10, 0x00, 0x92, 0x01, 0x02, 0x00]);
    assert_eq!(bus.sent(), ["602#4018100100000000"]);
    bus.advance(Duration::from_millis(100));
    assert_eq!(
        bus.error(2),
        "node 2 [D] vendor-ID 0x1018:01 could not be read: no answer within 100 ms"
    );
    // 0x1000 refused (0x06020000, the object does not exist): B, in the node's words.
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    bus.feed(0x702, &[0x00]);
    bus.sent();
    bus.feed(0x582, &[0x80, 0x00, 0x10, 0x00, 0x00, 0x00, 0x02, 0x06]);
    assert_eq!(
        bus.error(2),
        "node 2 [B] device type 0x1000:00 could not be read: the node refused it with 0x06020000 \
         (Object does not exist in the object dictionary)"
    );
}

#[test]
fn before_its_boot_up_only_a_kept_alive_slave_s_heartbeat_counts() {
    // Reset, not kept alive: heartbeats from before the reset took effect are passed over.
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    bus.feed(0x702, &[0x05]);
    bus.feed(0x702, &[0x7F]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    assert_eq!(bus.m.nodes().next().unwrap().state, NodeState::Resetting);
    bus.feed(0x702, &[0x00]);
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
    // Kept alive and pre-operational: booted at its heartbeat.
    let mut s = slave();
    s.assignment |= 0x10;
    let mut bus = Bus::new(plan(vec![s.clone()], 0x01));
    bus.m.start(bus.now);
    assert_eq!(bus.sent(), Vec::<String>::new(), "no reset");
    bus.feed(0x702, &[0x7F]);
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
    // Kept alive and operational: up once, not booted (L).
    let mut bus = Bus::new(plan(vec![s], 0x01));
    bus.m.start(bus.now);
    bus.feed(0x702, &[0x05]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    let r = bus.m.nodes().next().unwrap();
    assert_eq!((r.boots, r.kept, r.identity), (1, true, [None; 5]));
}

#[test]
fn a_boot_up_while_its_heartbeat_is_awaited_starts_the_boot_again() {
    let mut bus = Bus::new(plan(vec![slave()], 0x01));
    configured(&mut bus);
    bus.feed(0x702, &[0x00]);
    assert_eq!(bus.sent(), ["602#4000100000000000"]);
    assert_eq!(bus.states(2).last().map(String::as_str), Some("checking"));
}

#[test]
fn without_a_consumer_time_heartbeats_ask_for_no_call() {
    let mut s = slave();
    s.heartbeat_ms = 0;
    let mut bus = Bus::new(plan(vec![s], 0x01));
    configured(&mut bus);
    assert_eq!(bus.sent(), ["000#0102"]);
    bus.feed(0x702, &[0x05]);
    bus.advance(Duration::from_secs(10));
    assert_eq!(bus.m.poll_timeout(), None);
    assert_eq!(bus.states(2).last().map(String::as_str), Some("up"));
}

#[test]
fn a_slave_0x1f81_does_not_boot_is_only_watched() {
    let mut s = slave();
    s.assignment = 0x01;
    let mut bus = Bus::new(plan(vec![s], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    bus.feed(0x702, &[0x00]);
    assert_eq!(bus.sent(), Vec::<String>::new());
    assert_eq!(bus.states(2), ["watched"]);
    // Not mandatory in effect: the network is up without it.
    assert!(bus.m.network_up());
}

#[test]
fn a_master_0x1f80_keeps_pre_operational_beats_0x7f_when_the_network_is_up() {
    // 0x1F80 = 0x05: bit 2, the master does not enter Operational itself.
    let mut p = plan(vec![slave()], 0x05);
    p.heartbeat_ms = 100;
    let mut bus = Bus::new(p);
    boot(&mut bus);
    bus.advance(Duration::from_millis(100));
    let beats: Vec<String> = bus
        .sent()
        .into_iter()
        .filter(|f| f.starts_with("701#"))
        .collect();
    assert_eq!(beats, ["701#7F"]);
}

#[test]
fn a_node_holding_the_configuration_s_stamp_is_not_configured_again() {
    let mut s = slave();
    s.stamp = Some([14000, 43_200_000]);
    for sub in [1u8, 2] {
        s.configuration.push(ConfigEntry {
            entry: Entry::new(
                0x1020,
                sub,
                s.stamp.unwrap()[usize::from(sub) - 1]
                    .to_le_bytes()
                    .to_vec(),
            ),
            origin: "drive.dcf:10".into(),
        });
    }
    let read_stamp = |bus: &mut Bus, date: u32, time: u32| {
        identity(bus, 0x360, 7);
        assert_eq!(bus.sent(), ["602#4020100100000000"]);
        let d = date.to_le_bytes();
        bus.feed(0x582, &[0x43, 0x20, 0x10, 0x01, d[0], d[1], d[2], d[3]]);
        if date != 14000 {
            return;
        }
        assert_eq!(bus.sent(), ["602#4020100200000000"]);
        let t = time.to_le_bytes();
        bus.feed(0x582, &[0x43, 0x20, 0x10, 0x02, t[0], t[1], t[2], t[3]]);
    };
    // The same date and time: straight to its heartbeat, nothing written.
    let mut bus = Bus::new(plan(vec![s.clone()], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    read_stamp(&mut bus, 14000, 43_200_000);
    assert_eq!(bus.sent(), Vec::<String>::new());
    bus.feed(0x702, &[0x7F]);
    assert_eq!(bus.sent(), ["000#0102"]);
    let r = bus.m.nodes().next().unwrap();
    assert_eq!((r.current, r.configured), (true, (0, 3)));
    // Another time: the configuration is written, the stamp last.
    let mut bus = Bus::new(plan(vec![s.clone()], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    read_stamp(&mut bus, 14000, 1);
    assert_eq!(bus.sent(), ["602#2B17100064000000"]);
    bus.feed(0x582, &[0x60, 0x17, 0x10, 0x00, 0, 0, 0, 0]);
    assert_eq!(bus.sent(), ["602#23201001B0360000"]);
    bus.feed(0x582, &[0x60, 0x20, 0x10, 0x01, 0, 0, 0, 0]);
    assert_eq!(bus.sent(), ["602#23201002002E9302"]);
    assert!(!bus.m.nodes().next().unwrap().current);
    // Another date: written too, without reading the time.
    let mut bus = Bus::new(plan(vec![s.clone()], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    read_stamp(&mut bus, 13999, 0);
    assert_eq!(bus.sent(), ["602#2B17100064000000"]);
    // No 0x1020 (0x06020000): written, no failure.
    let mut bus = Bus::new(plan(vec![s], 0x01));
    bus.m.start(bus.now);
    bus.sent();
    identity(&mut bus, 0x360, 7);
    bus.sent();
    bus.feed(0x582, &[0x80, 0x20, 0x10, 0x01, 0x00, 0x00, 0x02, 0x06]);
    assert_eq!(bus.sent(), ["602#2B17100064000000"]);
    assert_eq!(bus.error(2), "");
}

#[test]
fn a_bus_description_s_plan_names_the_lines_of_its_values() {
    let eds = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/drive.eds");
    let yml = format!(
        "master:\n  node_id: 1\n\ndrive:\n  dcf: {}\n  node_id: 2\n  revision_number: 0x10001\n  \
         heartbeat_producer: 100\n  sdo:\n    - {{index: 0x6060, value: 1}}\n",
        eds.display()
    );
    let bus = canopen_net::Bus::parse(&yml, "bus.yml").unwrap();
    let mut load = |dcf: &str| {
        let (_, mut devices) =
            od::load::load(std::path::Path::new(dcf)).map_err(|e| e.to_string())?;
        let text = std::fs::read(dcf).unwrap();
        Ok(canopen_net::SlaveFile::new(devices.swap_remove(0), &text))
    };
    let opts = canopen_net::GenOptions::default();
    let g = canopen_net::generate(&bus, &mut load, &|_| None, opts).unwrap();
    let plan = Plan::from_generated(&g, "bus.yml");
    let s = &plan.slaves[0];
    let described = format!("bus.yml:5, {}", eds.display());
    assert_eq!(s.device_type.origin, described);
    assert_eq!(s.identity[0].origin, described);
    assert_eq!(s.identity[2].origin, "bus.yml:7 drive.revision_number");
    assert_eq!(s.identity[2].value, 0x10001);
    assert_eq!(s.heartbeat_origin, "bus.yml:8 drive.heartbeat_producer");
    let origins: Vec<(u16, &str)> = s
        .configuration
        .iter()
        .map(|c| (c.entry.index, c.origin.as_str()))
        .collect();
    assert_eq!(
        origins,
        [
            (0x1017, "bus.yml:8 drive.heartbeat_producer"),
            (0x6060, "bus.yml:10 drive.sdo")
        ]
    );
}

/// CiA 302-2's error status letters and what each means.
#[test]
fn each_error_status_has_its_letter_and_meaning() {
    use ErrorStatus::*;
    let table = [
        (A, 'A', "the node is no slave in 0x1F81"),
        (B, 'B', "no answer to the upload of 0x1000"),
        (C, 'C', "device type 0x1000 differs from 0x1F84"),
        (D, 'D', "vendor-ID 0x1018:01 differs from 0x1F85"),
        (E, 'E', "heartbeat event: no heartbeat in the consumer time"),
        (F, 'F', "node guarding event: no answer to node guarding"),
        (
            G,
            'G',
            "the objects for the software version check are not configured",
        ),
        (H, 'H', "a software update is needed and not allowed"),
        (
            I,
            'I',
            "a software update is needed and the program download failed",
        ),
        (J, 'J', "the configuration download failed"),
        (K, 'K', "no heartbeat while error control started"),
        (L, 'L', "the slave was operational already"),
        (M, 'M', "product code 0x1018:02 differs from 0x1F86"),
        (N, 'N', "revision number 0x1018:03 differs from 0x1F87"),
        (O, 'O', "serial number 0x1018:04 differs from 0x1F88"),
    ];
    for (status, letter, meaning) in table {
        assert_eq!((status.letter(), status.meaning()), (letter, meaning));
    }
}

/// A master DCF's 0x1F26 and 0x1F27 for a slave (here in its `master.bin`, whose entries the
/// master's objects take first) stamp that slave's configuration: written last, to 0x1020.
#[test]
fn a_master_dcf_s_configuration_date_and_time_stamp_the_slave_s_configuration() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/net");
    let text = std::fs::read_to_string(dir.join("basic.yml")).unwrap();
    let bus = canopen_net::Bus::parse(&text, "basic.yml").unwrap();
    let mut load = |dcf: &str| {
        let path = dir.join(dcf);
        let (_, mut devices) = od::load::load(&path).map_err(|e| e.to_string())?;
        let text = std::fs::read(&path).unwrap();
        Ok(canopen_net::SlaveFile::new(devices.swap_remove(0), &text))
    };
    let opts = canopen_net::GenOptions::default();
    let g = canopen_net::generate(&bus, &mut load, &|_| None, opts).unwrap();
    let file = |name: &str| {
        g.files
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, b)| b.clone())
    };
    let out = tempfile::tempdir().unwrap();
    let master = out.path().join("master.dcf");
    std::fs::write(&master, file("master.dcf").unwrap()).unwrap();
    let (_, mut devices) = od::load::load(&master).unwrap();
    let desc = devices.swap_remove(0);
    let master_text = std::fs::read_to_string(&master).unwrap();
    let stamped = |stamp: [u32; 2]| {
        let mut entries = canopen_net::concise::decode(&file("master.bin").unwrap()).unwrap();
        entries.push(Entry::new(0x1F26, 2, stamp[0].to_le_bytes().to_vec()));
        entries.push(Entry::new(0x1F27, 2, stamp[1].to_le_bytes().to_vec()));
        canopen_net::concise::encode(&entries)
    };
    let plan_with = |stamp: [u32; 2]| {
        let mut read = |name: &str| -> Result<Option<Vec<u8>>, String> {
            let base = std::path::Path::new(name)
                .file_name()
                .unwrap()
                .to_str()
                .unwrap();
            Ok(match base {
                "master.bin" => Some(stamped(stamp)),
                other => file(other),
            })
        };
        Plan::from_master_dcf(&desc, &master_text, "master.dcf", &mut read).unwrap()
    };
    let plan = plan_with([14000, 43_200_000]);
    let drive = plan.slaves.iter().find(|s| s.node_id == 2).unwrap();
    assert_eq!(drive.stamp, Some([14000, 43_200_000]));
    let tail: Vec<(u16, u8, Vec<u8>, &str)> = drive.configuration[drive.configuration.len() - 2..]
        .iter()
        .map(|c| {
            (
                c.entry.index,
                c.entry.sub,
                c.entry.data.clone(),
                c.origin.as_str(),
            )
        })
        .collect();
    assert_eq!(
        tail,
        [
            (
                0x1020,
                1,
                vec![0xB0, 0x36, 0, 0],
                "master.dcf: master.bin 0x1F26:02"
            ),
            (
                0x1020,
                2,
                vec![0x00, 0x2E, 0x93, 0x02],
                "master.dcf: master.bin 0x1F27:02"
            ),
        ]
    );
    // Neither given: no stamp, nothing added.
    let plain = plan_with([0, 0]);
    let drive_plain = plain.slaves.iter().find(|s| s.node_id == 2).unwrap();
    assert_eq!(drive_plain.stamp, None);
    assert_eq!(
        drive_plain.configuration.len() + 2,
        drive.configuration.len()
    );
}
