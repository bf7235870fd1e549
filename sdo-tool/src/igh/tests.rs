//! Each layout against IgH's format, worked out by hand from the format of its tool's commands
//! (CommandPdos, CommandXml, CommandCStruct, CommandSlaves, CommandSiiRead, DataTypeHandler) for
//! the same information.

use super::*;

fn entry(index: u16, sub: u8, bit_len: u8, name: &str) -> EntryConfig {
    EntryConfig {
        index,
        sub,
        bit_len,
        name: name.to_string(),
    }
}

fn sync(index: u8, start: u16, size: u16, control: u8, pdos: Vec<PdoConfig>) -> SyncConfig {
    SyncConfig {
        index,
        start_address: start,
        default_size: size,
        control,
        enable: 1,
        pdos,
    }
}

/// The example I/O device's SyncManagers: two mailboxes, SM2 (control 0x64: written by the master,
/// watchdog on) with RxPDO 0x1600 (an output bit, a 7-bit gap, an analog output) and SM3 (0x20) with
/// TxPDO 0x1A00.
fn io_syncs() -> Vec<SyncConfig> {
    vec![
        sync(0, 0x1000, 128, 0x26, vec![]),
        sync(1, 0x1080, 128, 0x22, vec![]),
        sync(
            2,
            0x1100,
            3,
            0x64,
            vec![PdoConfig {
                index: 0x1600,
                name: "Outputs".into(),
                entries: vec![
                    entry(0x7000, 1, 1, "Output 1"),
                    entry(0, 0, 7, ""),
                    entry(0x7010, 1, 16, "Analog output"),
                ],
            }],
        ),
        sync(
            3,
            0x1180,
            3,
            0x20,
            vec![PdoConfig {
                index: 0x1A00,
                name: "Inputs".into(),
                entries: vec![entry(0x6000, 1, 1, "Input 1")],
            }],
        ),
    ]
}

/// `pdos`: `SM%u: PhysAddr 0x%04x, DefaultSize %4u, ControlRegister 0x%02x, Enable %u`, the PDOs
/// with R or T by the control register's bit 2, entries with the bit length in two columns.
#[test]
fn pdos_layout() {
    assert_eq!(
        pdos(&io_syncs()),
        concat!(
            "SM0: PhysAddr 0x1000, DefaultSize  128, ControlRegister 0x26, Enable 1\n",
            "SM1: PhysAddr 0x1080, DefaultSize  128, ControlRegister 0x22, Enable 1\n",
            "SM2: PhysAddr 0x1100, DefaultSize    3, ControlRegister 0x64, Enable 1\n",
            "  RxPDO 0x1600 \"Outputs\"\n",
            "    PDO entry 0x7000:01,  1 bit, \"Output 1\"\n",
            "    PDO entry 0x0000:00,  7 bit, \"\"\n",
            "    PDO entry 0x7010:01, 16 bit, \"Analog output\"\n",
            "SM3: PhysAddr 0x1180, DefaultSize    3, ControlRegister 0x20, Enable 1\n",
            "  TxPDO 0x1a00 \"Inputs\"\n",
            "    PDO entry 0x6000:01,  1 bit, \"Input 1\"\n",
        )
    );
    assert_eq!(pdos(&[]), "");
}

fn tx_slave(position: u16, name: &str) -> SlaveConfig {
    SlaveConfig {
        position,
        identity: [0xABC, 0x191, 0x10001, 1],
        order: "io-device".into(),
        name: name.into(),
        syncs: vec![
            sync(0, 0x1000, 128, 0x26, vec![]),
            sync(
                1,
                0x1180,
                3,
                0x20,
                vec![PdoConfig {
                    index: 0x1A00,
                    name: "In & out".into(),
                    entries: vec![
                        entry(0x6000, 1, 1, "Input 1"),
                        entry(0, 0, 3, ""),
                        entry(0x6001, 2, 4, "Nibble"),
                        entry(0x6010, 1, 16, "Analog input"),
                        entry(0x6020, 0, 80, "Text"),
                    ],
                }],
            ),
        ],
    }
}

/// IgH's `ethercat xml` for one slave: the vendor in decimal, product and revision as `#x` and 8
/// hex digits, the name in CDATA, each Sm with `#x` addresses, each PDO with `Fixed="1"
/// Mandatory="1"` and its entries (a gap without SubIndex, Name and DataType; DataType BOOL, UINTn,
/// STRING(n) or BITn from the bit length).
const ONE_SLAVE: &str = r##"<?xml version="1.0" ?>
<EtherCATInfo>
  <!-- Slave 1 -->
  <Vendor>
    <Id>2748</Id>
  </Vendor>
  <Descriptions>
    <Devices>
      <Device>
        <Type ProductCode="#x00000191" RevisionNo="#x00010001">io-device</Type>
        <Name><![CDATA[I/O <8> & more ]]]]><![CDATA[> x]]></Name>
        <Sm Enable="1" StartAddress="#x1000" ControlByte="#x26" DefaultSize="128" />
        <Sm Enable="1" StartAddress="#x1180" ControlByte="#x20" DefaultSize="3" />
        <TxPdo Sm="1" Fixed="1" Mandatory="1">
          <Index>#x1a00</Index>
          <Name>In &amp; out</Name>
          <Entry>
            <Index>#x6000</Index>
            <SubIndex>1</SubIndex>
            <BitLen>1</BitLen>
            <Name>Input 1</Name>
            <DataType>BOOL</DataType>
          </Entry>
          <Entry>
            <Index>#x0000</Index>
            <BitLen>3</BitLen>
          </Entry>
          <Entry>
            <Index>#x6001</Index>
            <SubIndex>2</SubIndex>
            <BitLen>4</BitLen>
            <Name>Nibble</Name>
            <DataType>BIT4</DataType>
          </Entry>
          <Entry>
            <Index>#x6010</Index>
            <SubIndex>1</SubIndex>
            <BitLen>16</BitLen>
            <Name>Analog input</Name>
            <DataType>UINT16</DataType>
          </Entry>
          <Entry>
            <Index>#x6020</Index>
            <SubIndex>0</SubIndex>
            <BitLen>80</BitLen>
            <Name>Text</Name>
            <DataType>STRING(10)</DataType>
          </Entry>
        </TxPdo>
      </Device>
    </Devices>
  </Descriptions>
</EtherCATInfo>
"##;

#[test]
fn xml_layout_of_one_slave() {
    assert_eq!(xml(&[tx_slave(1, "I/O <8> & more ]]> x")]), ONE_SLAVE);
}

/// Several slaves: an EtherCATInfoList, each EtherCATInfo two spaces in; a slave without a name has
/// no Name element.
#[test]
fn xml_layout_of_a_list() {
    let mut second = tx_slave(2, "");
    second.syncs.truncate(1);
    let text = xml(&[tx_slave(1, "I/O <8> & more ]]> x"), second]);
    let mut want = String::from("<?xml version=\"1.0\" ?>\n<EtherCATInfoList>\n");
    for line in ONE_SLAVE.lines().skip(1) {
        want.push_str("  ");
        want.push_str(line);
        want.push('\n');
    }
    want.push_str(concat!(
        "  <EtherCATInfo>\n",
        "    <!-- Slave 2 -->\n",
        "    <Vendor>\n",
        "      <Id>2748</Id>\n",
        "    </Vendor>\n",
        "    <Descriptions>\n",
        "      <Devices>\n",
        "        <Device>\n",
        "          <Type ProductCode=\"#x00000191\" RevisionNo=\"#x00010001\">io-device</Type>\n",
        "          <Sm Enable=\"1\" StartAddress=\"#x1000\" ControlByte=\"#x26\" DefaultSize=\"128\" />\n",
        "        </Device>\n",
        "      </Devices>\n",
        "    </Descriptions>\n",
        "  </EtherCATInfo>\n",
        "</EtherCATInfoList>\n",
    ));
    assert_eq!(text, want);
}

/// The project's ESI reader takes IgH's layout: identity, names, SyncManagers and PDOs as written.
#[test]
fn xml_reads_back() {
    let devices = od::esi::read_all(ONE_SLAVE.as_bytes(), "one.xml").unwrap();
    assert_eq!(devices.len(), 1);
    let d = &devices[0];
    assert_eq!(
        (
            d.identity.vendor_id,
            d.identity.product_code,
            d.identity.revision
        ),
        (0xABC, 0x191, 0x10001)
    );
    assert_eq!(d.identity.order_code, "io-device");
    assert_eq!(d.identity.product_name, "I/O <8> & more ]]> x");
    let ec = d.ethercat.as_ref().unwrap();
    assert_eq!(ec.sync_managers.len(), 2);
    assert_eq!(ec.sync_managers[1].start_address, 0x1180);
    assert_eq!(ec.sync_managers[1].control_byte, 0x20);
    assert_eq!(ec.tx_pdos.len(), 1);
    let p = &ec.tx_pdos[0];
    assert_eq!(
        (p.index, p.name.as_str(), p.sm),
        (0x1A00, "In & out", Some(1))
    );
    let entries: Vec<(u16, u8, u16)> = p
        .entries
        .iter()
        .map(|e| (e.index, e.sub, e.bit_len))
        .collect();
    assert_eq!(
        entries,
        [
            (0x6000, 1, 1),
            (0, 0, 3),
            (0x6001, 2, 4),
            (0x6010, 1, 16),
            (0x6020, 0, 80)
        ]
    );
    let list = xml(&[tx_slave(1, "a"), tx_slave(2, "b")]);
    let devices = od::esi::read_all(list.as_bytes(), "list.xml").unwrap();
    assert_eq!(devices.len(), 2);
    assert_eq!(devices[1].identity.product_name, "b");
}

/// IgH's `ethercat cstruct`: the header comment with the order code, the entries, the PDOs
/// (offsets into the entries), the SyncManagers (direction by control bit 2, watchdog by bit 6,
/// offsets into the PDOs, NULL without PDOs) and the terminating `{0xff}`; `*/` in a name cannot end
/// the comment.
#[test]
fn cstruct_layout() {
    let mut syncs = io_syncs();
    syncs[3].pdos.push(PdoConfig {
        index: 0x1A01,
        name: String::new(),
        entries: vec![],
    });
    let slave = SlaveConfig {
        position: 3,
        identity: [0xABC, 0x191, 0x10001, 1],
        order: "io */ device".into(),
        name: "I/O".into(),
        syncs,
    };
    assert_eq!(
        cstruct(&slave),
        concat!(
            "/* Master 0, Slave 3, \"io * / device\"\n",
            " * Vendor ID:       0x00000abc\n",
            " * Product code:    0x00000191\n",
            " * Revision number: 0x00010001\n",
            " */\n",
            "\n",
            "ec_pdo_entry_info_t slave_3_pdo_entries[] = {\n",
            "    {0x7000, 0x01, 1}, /* Output 1 */\n",
            "    {0x0000, 0x00, 7},\n",
            "    {0x7010, 0x01, 16}, /* Analog output */\n",
            "    {0x6000, 0x01, 1}, /* Input 1 */\n",
            "};\n",
            "\n",
            "ec_pdo_info_t slave_3_pdos[] = {\n",
            "    {0x1600, 3, slave_3_pdo_entries + 0}, /* Outputs */\n",
            "    {0x1a00, 1, slave_3_pdo_entries + 3}, /* Inputs */\n",
            "    {0x1a01, 0, NULL},\n",
            "};\n",
            "\n",
            "ec_sync_info_t slave_3_syncs[] = {\n",
            "    {0, EC_DIR_OUTPUT, 0, NULL, EC_WD_DISABLE},\n",
            "    {1, EC_DIR_INPUT, 0, NULL, EC_WD_DISABLE},\n",
            "    {2, EC_DIR_OUTPUT, 1, slave_3_pdos + 0, EC_WD_ENABLE},\n",
            "    {3, EC_DIR_INPUT, 2, slave_3_pdos + 1, EC_WD_DISABLE},\n",
            "    {0xff}\n",
            "};\n",
            "\n",
        )
    );
    // Without SyncManagers nothing; without PDOs no entry or PDO array.
    let mut bare = slave.clone();
    bare.syncs.clear();
    assert_eq!(cstruct(&bare), "");
    bare.syncs = vec![sync(0, 0x1000, 128, 0x26, vec![])];
    bare.order.clear();
    assert_eq!(
        cstruct(&bare),
        concat!(
            "/* Master 0, Slave 3\n",
            " * Vendor ID:       0x00000abc\n",
            " * Product code:    0x00000191\n",
            " * Revision number: 0x00010001\n",
            " */\n",
            "\n",
            "ec_sync_info_t slave_3_syncs[] = {\n",
            "    {0, EC_DIR_OUTPUT, 0, NULL, EC_WD_DISABLE},\n",
            "    {0xff}\n",
            "};\n",
            "\n",
        )
    );
}

/// IgH's one-line `slaves`: each column as wide as its widest entry (position and alias to the
/// right, the relative position and the state to the left); the alias of the last slave with one
/// and the count since it.
#[test]
fn slaves_list_layout() {
    let line = |position, alias, state: &str, error, name: &str| SlaveLine {
        position,
        alias,
        state: state.into(),
        error,
        name: name.into(),
    };
    let lines = [
        line(9, 0, "PREOP", false, "A"),
        line(10, 4660, "OP", false, "B"),
        line(11, 0, "SAFEOP+ERROR", true, "0x00000abc:0x00000191"),
    ];
    assert_eq!(
        slaves_list(&lines),
        concat!(
            " 9     0:0  PREOP         +  A\n",
            "10  4660:0  OP            +  B\n",
            "11  4660:1  SAFEOP+ERROR  E  0x00000abc:0x00000191\n",
        )
    );
    assert_eq!(identity_name(0xABC, 0x191), "0x00000abc:0x00000191");
    assert_eq!(slaves_list(&[]), "");
}

/// The topology as IgH's master walks it: port 0 to the slave before, the open ports in the order
/// 3, 1, 2 to the next ones. DL status bit 8 + 2·port: that port's loop is closed.
#[test]
fn the_next_slave_on_each_port() {
    let closed = |ports: &[usize]| ports.iter().map(|p| 1u16 << (8 + 2 * p)).sum::<u16>();
    // A line of three.
    let line = [closed(&[2, 3]), closed(&[2, 3]), closed(&[1, 2, 3])];
    assert_eq!(
        next_slaves(&line),
        [
            [None, Some(2), None, None],
            [Some(1), Some(3), None, None],
            [Some(2), None, None, None],
        ]
    );
    // A junction: port 3 first, then port 1.
    let junction = [closed(&[2]), closed(&[1, 2, 3]), closed(&[1, 2, 3])];
    assert_eq!(
        next_slaves(&junction),
        [
            [None, Some(3), None, Some(2)],
            [Some(1), None, None, None],
            [Some(1), None, None, None],
        ]
    );
    // An open port with no slave left: the walk stops there.
    assert_eq!(next_slaves(&[closed(&[2, 3])]), [[None; 4]]);
    assert!(next_slaves(&[]).is_empty());
}

/// An SII made by hand for `slaves --verbose`: vendor 0xABC, product 0x191, revision 0x10001,
/// serial 2; bootstrap mailbox 0x1000/64 and 0x1040/64, standard 0x1800/128 and 0x1880/128, CoE and
/// FoE (0x000C); Strings "grp", "ord", "Dev"; General: group 1, order 2, name 3, CoE details 0x27,
/// flags 0x02 (not LRW), −5 mA.
fn verbose_sii() -> Vec<u8> {
    let mut b = vec![0u8; 0x80];
    let put16 = |b: &mut Vec<u8>, word: usize, v: u16| {
        b[2 * word..2 * word + 2].copy_from_slice(&v.to_le_bytes())
    };
    for (word, v) in [
        (8, 0x0ABC),
        (10, 0x0191),
        (12, 0x0001),
        (13, 0x0001),
        (14, 0x0002),
        (0x14, 0x1000),
        (0x15, 64),
        (0x16, 0x1040),
        (0x17, 64),
        (0x18, 0x1800),
        (0x19, 128),
        (0x1A, 0x1880),
        (0x1B, 128),
        (0x1C, 0x000C),
    ] {
        put16(&mut b, word, v);
    }
    b.extend_from_slice(&[
        0x0A, 0, 7, 0, 3, 3, b'g', b'r', b'p', 3, b'o', b'r', b'd', 3,
    ]);
    b.extend_from_slice(b"Dev");
    b.push(0);
    let mut g = [0u8; 32];
    g[0] = 1;
    g[2] = 2;
    g[3] = 3;
    g[5] = 0x27;
    g[11] = 0x02;
    g[12..14].copy_from_slice(&(-5i16).to_le_bytes());
    b.extend_from_slice(&[0x1E, 0, 16, 0]);
    b.extend_from_slice(&g);
    b.extend_from_slice(&[0xFF, 0xFF]);
    b
}

/// `slaves --verbose`: IgH's block, with the ports from 0x0007 and the DL status, DC without a
/// system time ("delay measurement only"), the mailboxes and protocols from the SII header, the
/// General category's strings, CoE details and flags.
#[test]
fn slaves_verbose_layout() {
    let line = SlaveLine {
        position: 2,
        alias: 7,
        state: "PREOP".into(),
        error: false,
        name: "Dev".into(),
    };
    // Port 0: link, communication; port 1 closed; ports 2 and 3 closed.
    let dl = (1 << 4) | (1 << 9) | (1 << 10) | (1 << 12) | (1 << 14);
    let esc = EscInfo {
        ports: 0x0F,
        features: 0x0004,
        dc_system_time: false,
        dl_status: dl,
        next: [Some(1), None, None, None],
    };
    assert_eq!(
        slaves_verbose(&line, &verbose_sii(), &esc),
        concat!(
            "=== Slave 2 ===\n",
            "Alias: 7\n",
            "State: PREOP\n",
            "Flag: +\n",
            "Identity:\n",
            "  Vendor Id:       0x00000abc\n",
            "  Product code:    0x00000191\n",
            "  Revision number: 0x00010001\n",
            "  Serial number:   0x00000002\n",
            "DL information:\n",
            "  FMMU bit operation: no\n",
            "  Distributed clocks: yes, delay measurement only\n",
            "Port  Type  Link  Loop    Signal  NextSlave\n",
            "   0  MII   up    open    yes             1\n",
            "   1  MII   down  closed  no              -\n",
            "   2  N/A   down  closed  no              -\n",
            "   3  N/A   down  closed  no              -\n",
            "Mailboxes:\n",
            "  Bootstrap RX: 0x1000/64, TX: 0x1040/64\n",
            "  Standard  RX: 0x1800/128, TX: 0x1880/128\n",
            "  Supported protocols: CoE, FoE\n",
            "General:\n",
            "  Group: grp\n",
            "  Image name: \n",
            "  Order number: ord\n",
            "  Device name: Dev\n",
            "  CoE details:\n",
            "    Enable SDO: yes\n",
            "    Enable SDO Info: yes\n",
            "    Enable PDO Assign: yes\n",
            "    Enable PDO Configuration: no\n",
            "    Enable Upload at startup: no\n",
            "    Enable SDO complete access: yes\n",
            "  Flags:\n",
            "    Enable SafeOp: no\n",
            "    Enable notLRW: yes\n",
            "  Current consumption: -5 mA\n",
        )
    );
    // A slave whose SII could not be read: its identity zero, no mailboxes, no General; byte
    // FMMUs, 64-bit DC with a system time, E-bus and "not configured" ports.
    let esc = EscInfo {
        ports: 0b0000_0110,
        features: 0x000D,
        dc_system_time: true,
        dl_status: 0,
        next: [None; 4],
    };
    let failed = SlaveLine {
        alias: 0,
        error: true,
        ..line
    };
    assert_eq!(
        slaves_verbose(&failed, &[], &esc),
        concat!(
            "=== Slave 2 ===\n",
            "State: PREOP\n",
            "Flag: E\n",
            "Identity:\n",
            "  Vendor Id:       0x00000000\n",
            "  Product code:    0x00000000\n",
            "  Revision number: 0x00000000\n",
            "  Serial number:   0x00000000\n",
            "DL information:\n",
            "  FMMU bit operation: yes\n",
            "  Distributed clocks: yes, 64 bit\n",
            "Port  Type  Link  Loop    Signal  NextSlave\n",
            "   0  EBUS  down  open    no              -\n",
            "   1  N/C   down  open    no              -\n",
            "   2  N/A   down  open    no              -\n",
            "   3  N/A   down  open    no              -\n",
        )
    );
}

/// The DL information and the ports of `slaves --verbose` by each bit: no DC; DC with a 32-bit
/// system time; ports 1 to 3 with link (DL status bits 5–7) and communication (bits 11, 13, 15) and
/// open loops; a mailbox of a slave whose SII ends in its header (words 0x14–0x1C read, no identity
/// or General); a General category without CoE (FoE only): no CoE details.
#[test]
fn slaves_verbose_bit_by_bit() {
    let line = SlaveLine {
        position: 1,
        alias: 0,
        state: "INIT".into(),
        error: false,
        name: String::new(),
    };
    let ports = |s: &str| -> Vec<String> {
        s.lines()
            .skip_while(|l| !l.starts_with("DL information"))
            .take(7)
            .map(str::to_string)
            .collect()
    };
    let links = (1 << 5) | (1 << 6) | (1 << 7) | (1 << 11) | (1 << 13) | (1 << 15);
    let esc = EscInfo {
        ports: 0xFF,
        features: 0x0000,
        dc_system_time: true,
        dl_status: links,
        next: [None, Some(2), Some(3), Some(4)],
    };
    assert_eq!(
        ports(&slaves_verbose(&line, &[], &esc)),
        [
            "DL information:",
            "  FMMU bit operation: no",
            "  Distributed clocks: no",
            "Port  Type  Link  Loop    Signal  NextSlave",
            "   0  MII   down  open    no              -",
            "   1  MII   up    open    yes             2",
            "   2  MII   up    open    yes             3",
        ]
    );
    let dc32 = EscInfo {
        features: 0x0004,
        ..esc
    };
    let text = slaves_verbose(&line, &[], &dc32);
    assert!(
        text.contains("  Distributed clocks: yes, 32 bit\n"),
        "{text}"
    );
    assert!(
        text.ends_with("   3  MII   up    open    yes             4\n"),
        "{text}"
    );
    // An SII cut after word 0x1C: the mailboxes, nothing of the rest.
    let mut head = verbose_sii();
    head.truncate(0x3A);
    let text = slaves_verbose(&line, &head, &esc);
    assert!(
        text.ends_with(concat!(
            "Mailboxes:\n",
            "  Bootstrap RX: 0x1000/64, TX: 0x1040/64\n",
            "  Standard  RX: 0x1800/128, TX: 0x1880/128\n",
            "  Supported protocols: CoE, FoE\n",
        )),
        "{text}"
    );
    assert!(text.contains("  Vendor Id:       0x00000000\n"), "{text}");
    // FoE only: the General block without CoE details.
    let mut foe = verbose_sii();
    foe[0x38] = 0x08;
    let text = slaves_verbose(&line, &foe, &esc);
    assert!(text.contains("  Supported protocols: FoE\n"), "{text}");
    assert!(
        text.ends_with(concat!(
            "  Device name: Dev\n",
            "  Flags:\n",
            "    Enable SafeOp: no\n",
            "    Enable notLRW: yes\n",
            "  Current consumption: -5 mA\n",
        )),
        "{text}"
    );
}

/// `sii-read --verbose`: the header's 128 bytes 16 to a line, then each category with its type in
/// hex, its name and its length in words, its bytes 16 to a line (none for an empty one).
#[test]
fn sii_listing_layout() {
    let mut b: Vec<u8> = (0..0x80).collect();
    b.extend_from_slice(&[0x28, 0, 0, 0]);
    b.extend_from_slice(&[0x0A, 0, 9, 0]);
    b.extend(0xA0..0xB2u8);
    b.extend_from_slice(&[0x34, 0x12, 1, 0, 0xEE, 0xFF]);
    b.extend_from_slice(&[0xFF, 0xFF]);
    assert_eq!(
        sii_listing(&b),
        concat!(
            "SII Area:\n",
            "  00 01 02 03 04 05 06 07 08 09 0a 0b 0c 0d 0e 0f\n",
            "  10 11 12 13 14 15 16 17 18 19 1a 1b 1c 1d 1e 1f\n",
            "  20 21 22 23 24 25 26 27 28 29 2a 2b 2c 2d 2e 2f\n",
            "  30 31 32 33 34 35 36 37 38 39 3a 3b 3c 3d 3e 3f\n",
            "  40 41 42 43 44 45 46 47 48 49 4a 4b 4c 4d 4e 4f\n",
            "  50 51 52 53 54 55 56 57 58 59 5a 5b 5c 5d 5e 5f\n",
            "  60 61 62 63 64 65 66 67 68 69 6a 6b 6c 6d 6e 6f\n",
            "  70 71 72 73 74 75 76 77 78 79 7a 7b 7c 7d 7e 7f\n",
            "SII Category 0x0028 (FMMU), 0 words\n",
            "SII Category 0x000a (STRINGS), 9 words\n",
            "  a0 a1 a2 a3 a4 a5 a6 a7 a8 a9 aa ab ac ad ae af\n",
            "  b0 b1\n",
            "SII Category 0x1234 (unknown), 1 words\n",
            "  ee ff\n",
        )
    );
    // Only the header (a cut image): no category.
    assert_eq!(sii_listing(&b[..0x80]).lines().count(), 9);
}

/// IgH's `reg_read` output: `0x`, two hex digits per byte, the decimal value (signed for intN);
/// raw bytes each as `0x..`; a string as its text.
#[test]
fn register_values_as_igh_shows_them() {
    let t = |name| RegType::parse(name).unwrap();
    assert_eq!(t("uint16").format(&[0x30, 0x01]), "0x0130 304\n");
    assert_eq!(t("int16").format(&[0xFF, 0xFF]), "0xffff -1\n");
    assert_eq!(t("int16").format(&[0xFF, 0x00]), "0x00ff 255\n");
    assert_eq!(t("int32").format(&[0xFF, 0xFF, 0, 0]), "0x0000ffff 65535\n");
    assert_eq!(t("int8").format(&[0x80]), "0x80 -128\n");
    assert_eq!(t("uint8").format(&[0x80]), "0x80 128\n");
    assert_eq!(
        t("int32").format(&[0xFE, 0xFF, 0xFF, 0xFF]),
        "0xfffffffe -2\n"
    );
    assert_eq!(t("uint32").format(&[0x11, 0, 2, 0]), "0x00020011 131089\n");
    assert_eq!(
        t("uint64").format(&[0xFF; 8]),
        "0xffffffffffffffff 18446744073709551615\n"
    );
    assert_eq!(t("int64").format(&[0xFF; 8]), "0xffffffffffffffff -1\n");
    assert_eq!(t("raw").format(&[0x11, 0, 2, 0]), "0x11 0x00 0x02 0x00\n");
    assert_eq!(t("string").format(b"ab"), "ab\n");
    for name in [
        "int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64", "string", "raw",
    ] {
        assert_eq!(t(name).name(), name);
    }
    assert_eq!(RegType::parse("float"), None);
    assert_eq!(RegType::parse("u16"), None);
    assert_eq!(t("uint32").size(), Some(4));
    assert_eq!(t("raw").size(), None);
}

/// `reg_write`'s values: in the type's width, little-endian, within its range.
#[test]
fn register_values_as_igh_takes_them() {
    let t = |name| RegType::parse(name).unwrap();
    assert_eq!(t("uint8").encode("255"), Some(vec![255]));
    assert_eq!(t("uint8").encode("256"), None);
    assert_eq!(t("uint8").encode("-1"), None);
    assert_eq!(t("int8").encode("-128"), Some(vec![0x80]));
    assert_eq!(t("int8").encode("128"), None);
    assert_eq!(t("uint16").encode("0x1234"), Some(vec![0x34, 0x12]));
    assert_eq!(t("uint16").encode("010"), Some(vec![8, 0]), "octal");
    assert_eq!(t("int16").encode("-0x10"), Some(vec![0xF0, 0xFF]));
    assert_eq!(
        t("uint32").encode("4294967295"),
        Some(vec![0xFF, 0xFF, 0xFF, 0xFF])
    );
    assert_eq!(t("uint32").encode("4294967296"), None);
    assert_eq!(t("int64").encode("-1"), Some(vec![0xFF; 8]));
    assert_eq!(t("uint16").encode("x"), None);
    assert_eq!(t("string").encode("hi"), Some(b"hi".to_vec()));
    assert_eq!(t("raw").encode("01"), None);
}

/// IgH's numbers: `0x` hex, a leading 0 octal, else decimal.
#[test]
fn numbers_as_igh_takes_them() {
    for (text, want) in [
        ("0x1F", Some(31)),
        ("0X1f", Some(31)),
        ("017", Some(15)),
        ("17", Some(17)),
        ("0", Some(0)),
        ("00", Some(0)),
        ("-5", Some(-5)),
        ("+3", Some(3)),
        (" 12 ", Some(12)),
        ("08", None),
        ("0x", None),
        ("", None),
        ("abc", None),
        ("--1", None),
        ("-+1", None),
        ("0x-1", None),
        ("1.5", None),
    ] {
        assert_eq!(parse_number(text), want, "{text:?}");
    }
}

/// The SyncManagers and PDOs of an SII image: each PDO with the SyncManager its record names, a PDO
/// of none (0xFF) or of a SyncManager the image lacks left out, names from the strings.
#[test]
fn sii_syncs_from_an_image() {
    let mut b = vec![0u8; 0x80];
    b.extend_from_slice(&[0x0A, 0, 3, 0, 2, 1, b'A', 2, b'B', b'C']);
    b.extend_from_slice(&[0x29, 0, 4, 0]);
    b.extend_from_slice(&[0x00, 0x11, 0x02, 0x00, 0x64, 0x00, 0x01, 0x03]);
    // TxPDO 0x1A00 on SM0 with entry 0x6000:01 (8 bits, "B"); 0x1A01 on none; 0x1A02 on SM5.
    b.extend_from_slice(&[0x32, 0, 16, 0]);
    b.extend_from_slice(&[0x00, 0x1A, 1, 0, 0, 1, 0, 0]);
    b.extend_from_slice(&[0x00, 0x60, 1, 2, 5, 8, 0, 0]);
    b.extend_from_slice(&[0x01, 0x1A, 0, 0xFF, 0, 0, 0, 0]);
    b.extend_from_slice(&[0x02, 0x1A, 0, 5, 0, 0, 0, 0]);
    b.extend_from_slice(&[0xFF, 0xFF]);
    let image = od::sii::Image::read(&b).unwrap();
    assert_eq!(
        sii_syncs(&image),
        [SyncConfig {
            index: 0,
            start_address: 0x1100,
            default_size: 2,
            control: 0x64,
            enable: 1,
            pdos: vec![PdoConfig {
                index: 0x1A00,
                name: "A".into(),
                entries: vec![entry(0x6000, 1, 8, "BC")],
            }],
        }]
    );
    let all = sii_pdos(&image);
    let indices: Vec<(Option<u8>, u16)> = all.iter().map(|(sm, p)| (*sm, p.index)).collect();
    assert_eq!(
        indices,
        [(Some(0), 0x1A00), (None, 0x1A01), (Some(5), 0x1A02)]
    );
}

/// The value `reg-read --json` gives: the bytes little-endian, the top bit of the type's width the
/// sign for a signed type (FE FF: -2 as int16, 65534 as uint16; 01 80 00 00: 32769 as int32, whose
/// sign bit is byte 3's); none for a string or raw bytes.
#[test]
fn register_values_as_json_gives_them() {
    let t = |name| RegType::parse(name).unwrap();
    assert_eq!(t("int16").value(&[0xFE, 0xFF]), Some(-2));
    assert_eq!(t("uint16").value(&[0xFE, 0xFF]), Some(65_534));
    assert_eq!(t("int32").value(&[0x01, 0x80, 0x00, 0x00]), Some(32_769));
    assert_eq!(t("int8").value(&[0x80]), Some(-128));
    assert_eq!(t("int64").value(&[0xFF; 8]), Some(-1), "all 64 bits set");
    assert_eq!(
        t("uint64").value(&[0xFF; 8]),
        Some(18_446_744_073_709_551_615)
    );
    assert_eq!(t("string").value(b"ab"), None);
    assert_eq!(t("raw").value(&[1, 2]), None);
}
