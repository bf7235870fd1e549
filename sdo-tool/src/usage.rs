//! [`UsageError`]: what is wrong with the words of a command (exit code 2), one variant for each
//! kind of mistake, each with the message the user sees.

use std::net::SocketAddr;
use std::path::PathBuf;

use od::dict::Address;

/// The command's words are wrong: the node, the object, the type, the value, a file, an option, or
/// a command where it is not available.
#[derive(Debug, thiserror::Error)]
pub enum UsageError {
    /// The command line does not parse: the parser's own message.
    #[error("{0}")]
    CommandLine(String),
    /// A node-ID outside 1–127.
    #[error("node {node} is not 1 to 127")]
    Node {
        /// The node-ID given.
        node: u8,
    },
    /// `nmt`: a node-ID outside 1–127 (0 is all nodes).
    #[error("node {node} is not 1 to 127 or all")]
    NmtNode {
        /// The node-ID given.
        node: u8,
    },
    /// `nmt`: a node that is neither a node-ID nor `all`.
    #[error("node {text:?} is not 1 to 127 or all")]
    NmtNodeText {
        /// The node as given.
        text: String,
    },
    /// `send`: a frame that is not cansend's ID#DATA.
    #[error("frame {text:?}: {why}")]
    Frame {
        /// The frame as given.
        text: String,
        /// What is wrong with it.
        why: String,
    },
    /// `nmt`: a command that is none of start, stop, preop, reset, reset-comm.
    #[error("NMT command {command:?} is not start, stop, preop, reset or reset-comm")]
    NmtCommand {
        /// The command as given.
        command: String,
    },
    /// `lss`: an LSS address that is not VENDOR:PRODUCT:REVISION:SERIAL.
    #[error("LSS address {text:?} is not VENDOR:PRODUCT:REVISION:SERIAL (e.g. 0x5A:0x402:1:2)")]
    LssAddress {
        /// The address as given.
        text: String,
    },
    /// `lss identify`: a range that is not VENDOR:PRODUCT:REVISIONS:SERIALS.
    #[error("LSS range {text:?} is not VENDOR:PRODUCT:REVISIONS:SERIALS, REVISIONS and SERIALS a number or LOW-HIGH (e.g. 0xABC:0x402:0x10000-0x1FFFF:1-100)")]
    LssRange {
        /// The range as given.
        text: String,
    },
    /// `lss`: a node-ID outside 1–127.
    #[error("node-ID {text:?} is not 1 to 127")]
    LssNodeId {
        /// The node-ID as given.
        text: String,
    },
    /// `lss set-id`: neither ADDRESS NEW_ID nor --fastscan NEW_ID….
    #[error("lss set-id ADDRESS NEW_ID, or lss set-id --fastscan NEW_ID…")]
    LssSetId,
    /// `lss bitrate`: a bit rate the CiA 301 table does not have.
    #[error("bit rate {kbit} kbit/s is not 1000, 800, 500, 250, 125, 100, 50, 20 or 10")]
    LssBitRate {
        /// The bit rate given.
        kbit: u32,
    },
    /// `lss switch`: a state that is neither waiting nor configuration.
    #[error("LSS state {text:?} is not waiting or configuration")]
    LssState {
        /// The state as given.
        text: String,
    },
    /// `lss assign`: more nodes without a node-ID than node-IDs from FIRST_ID to 127.
    #[error("more nodes without a node-ID than node-IDs from {first} to 127")]
    LssNodeIdsUsedUp {
        /// FIRST_ID.
        first: u8,
    },
    /// With `--ethercat`: a slave position beyond the chain.
    #[error(
        "slave position {position} is not 1 to {count} (the chain on {interface} has {count} slave{})",
        if *count == 1 { "" } else { "s" }
    )]
    SlavePosition {
        /// The position given.
        position: u16,
        /// The slaves of the chain.
        count: usize,
        /// The chain's network interface.
        interface: String,
    },
    /// `foe-write -` without the name on the slave.
    #[error("foe-write - reads standard input: name the file on the slave with -o NAME")]
    FoeStdinName,
    /// `foe-read --json` to standard output.
    #[error("foe-read --json: give -o FILE (the file's bytes and the JSON line would mix)")]
    FoeJsonOutput,
    /// OBJECT is a name the description does not give to one entry.
    #[error("object {text:?}: {error}")]
    UnknownName {
        /// OBJECT as given.
        text: String,
        /// What the description says of the name.
        error: od::LookupError,
    },
    /// OBJECT is not `INDEX:SUB`, and names need a description.
    #[error("object {text:?} is not INDEX:SUB (e.g. 0x1018:01); names need --od")]
    NameWithoutDescription {
        /// OBJECT as given.
        text: String,
    },
    /// TYPE is no CiA 309-3 type.
    #[error(
        "type {text:?} is not a CiA 309-3 type (b, i8–i64, u8–u64, x8–x64, r32, r64, vs, os, us, d, hex)"
    )]
    UnknownType {
        /// TYPE as given.
        text: String,
    },
    /// No type given, no description, and the node does not describe the entry.
    #[error("give the type (e.g. u16), or a description with --od")]
    TypeNeeded,
    /// The entry is not in the description.
    #[error("{address}: {error}")]
    NotInDescription {
        /// The entry.
        address: Address,
        /// What the description says of it.
        error: od::OdError,
    },
    /// The description's access refuses the transfer: a write-only entry is not read, a read-only
    /// one not written.
    #[error(
        "{address} ({name}) is {} ({access}) in the description: not {}",
        if *write { "read-only" } else { "write-only" },
        if *write { "written" } else { "read" }
    )]
    Access {
        /// The entry.
        address: Address,
        /// Its name.
        name: String,
        /// Its access in the description (`ro`, `wo`, `const`…).
        access: &'static str,
        /// A write was refused (else a read).
        write: bool,
    },
    /// The bytes read are no value of the type asked for.
    #[error(
        "{address}: {error}: the entry is of another type (read it as its own type, or as hex)"
    )]
    OtherType {
        /// The entry.
        address: Address,
        /// Why the bytes are no such value.
        error: od::ValueError,
    },
    /// The value is refused before anything is sent: no value of the type, or one the description
    /// refuses (length, limits).
    #[error("{address}: {why} (not sent)")]
    ValueRefused {
        /// The entry.
        address: Address,
        /// Why.
        why: String,
    },
    /// `write` with a type and no value after it.
    #[error(
        "{address}: the value is missing after the type {text} (write NODE OBJECT [TYPE] VALUE; {data_type} as TYPE)"
    )]
    ValueMissing {
        /// The entry.
        address: Address,
        /// The type as given, in the value's place.
        text: String,
        /// The type it names.
        data_type: od::DataType,
    },
    /// `write` without `[TYPE] VALUE`.
    #[error("write NODE OBJECT [TYPE] VALUE")]
    WriteArguments,
    /// A description file (`--od`, `apply`'s DCF) that does not load.
    #[error("{what} {}: {error}", path.display())]
    Description {
        /// Where it was given: `--od` or `apply`.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// Why it does not load.
        error: od::LoadError,
    },
    /// A description file without a device.
    #[error("{what} {}: no device in it", path.display())]
    NoDevice {
        /// Where it was given: `--od` or `apply`.
        what: &'static str,
        /// The file.
        path: PathBuf,
    },
    /// `list` without `--od`.
    #[error("list needs a description: --od FILE")]
    ListNeedsDescription,
    /// `dump` without `--od`.
    #[error("dump needs the node's description: --od FILE")]
    DumpNeedsDescription,
    /// A file that cannot be looked at, opened, created or written.
    #[error("{}: {error}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What the system said.
        error: std::io::Error,
    },
    /// A directory where a file is read.
    #[error("{}: a directory", path.display())]
    Directory {
        /// The directory.
        path: PathBuf,
    },
    /// `download`: a file that is no regular file (a FIFO, a device).
    #[error("{}: not a regular file", path.display())]
    NotRegularFile {
        /// The file.
        path: PathBuf,
    },
    /// `decode`: the log cannot be read on.
    #[error("{name}: {error}")]
    Log {
        /// The log's path, or `standard input`.
        name: String,
        /// What the system said.
        error: std::io::Error,
    },
    /// `decode`: a capture without a SocketCAN interface (an EtherCAT capture, say).
    #[error(
        "{name}: no SocketCAN interface in the capture ({}): decode names CAN frames only",
        if interfaces.is_empty() { "it describes none".to_string() } else { format!("its interfaces: {}", interfaces.join(", ")) }
    )]
    NoCanInCapture {
        /// The capture's path, or `standard input`.
        name: String,
        /// Its interfaces, as `NAME (link type N)`.
        interfaces: Vec<String>,
    },
    /// `net`: the bus description cannot be read or generated: the file, line, key and what.
    #[error("{0}")]
    Net(String),
    /// `net check`: what is wrong, counted (each was printed on its own line).
    #[error("{}: {count} problem{}", file.display(), if *count == 1 { "" } else { "s" })]
    NetProblems {
        /// The bus description.
        file: PathBuf,
        /// How many problems.
        count: usize,
    },
    /// `--bus` names a socketcand server to be, not a bus to join.
    #[error("sdo-tool joins a bus: socketcan:IFACE or socketcand://HOST:PORT/CHANNEL")]
    ListeningBus,
    /// `gateway --listen`: the address cannot be listened on.
    #[error("--listen {address}: {error}")]
    Listen {
        /// The address.
        address: SocketAddr,
        /// What the system said.
        error: std::io::Error,
    },
    /// An EtherCAT command without `--ethercat`.
    #[error("`{command}` is an EtherCAT command: give --ethercat IFACE")]
    EthercatOnly {
        /// The command's name.
        command: &'static str,
    },
    /// The capture file of `--capture` cannot be created.
    #[error("--capture {0}")]
    Capture(#[source] crate::link::CaptureError),
    /// `--capture` with a command that opens no bus and no interface.
    #[error("`{command}` uses no bus and no EtherCAT interface: --capture has nothing to record")]
    CaptureWithoutLink {
        /// The command's name.
        command: &'static str,
    },
    /// A command for one slave on a chain of several, without the slave's position.
    #[error(
        "`{command}` takes one slave: the chain on {interface} has {count}: give {how} (1 = first)"
    )]
    OneSlave {
        /// The command's name.
        command: &'static str,
        /// How the command takes a position: `POS`, or `-p POS` where a file comes first.
        how: &'static str,
        /// The chain's network interface.
        interface: String,
        /// Its slaves.
        count: u16,
    },
    /// A number that is none (IgH's notation: decimal, `0x…` hexadecimal, `0…` octal).
    #[error("{what} {text:?} is not a number (decimal, 0x… hex or 0… octal)")]
    Number {
        /// What the number is (`address`, `size`, `alias`, `slave position`).
        what: &'static str,
        /// As given.
        text: String,
    },
    /// `reg-read`/`reg-write`: an address beyond the ESC's registers.
    #[error(
        "address 0x{address:X} is not a register (0x0000 to 0x0FFF; the process memory above \
         belongs to the SyncManagers)"
    )]
    RegisterAddress {
        /// The address given.
        address: i128,
    },
    /// `reg-read`/`reg-write`: a range that runs past the registers.
    #[error("0x{address:04X} + {size} bytes runs past the registers' end at 0x0FFF")]
    RegisterRange {
        /// The address.
        address: u16,
        /// The bytes.
        size: usize,
    },
    /// `reg-read` of no bytes, or `reg-write` of none.
    #[error("{what} of 0 bytes: give 1 or more")]
    NoBytes {
        /// `a read` or `a write`.
        what: &'static str,
    },
    /// `reg-read` without SIZE and without a type that has a size.
    #[error("give SIZE: {type_name} has no size of its own")]
    SizeNeeded {
        /// The type (`raw`, `string`).
        type_name: &'static str,
    },
    /// `--type` of `reg-read`/`reg-write` that IgH's tool does not have.
    #[error(
        "type {text:?} is not int8, int16, int32, int64, uint8, uint16, uint32, uint64, string or \
         raw{}", if *write { " (raw is for reads)" } else { "" }
    )]
    RegType {
        /// As given.
        text: String,
        /// For a write (where raw is none).
        write: bool,
    },
    /// `reg-write`: a value that is none of the type.
    #[error("{text:?} is no {type_name} value")]
    RegValue {
        /// As given.
        text: String,
        /// The type.
        type_name: &'static str,
    },
    /// `alias`: an alias outside 0–65535.
    #[error("alias {text:?} is not 0 to 65535")]
    Alias {
        /// As given.
        text: String,
    },
    /// `alias` for every slave of a chain of several without `--force`.
    #[error("this writes alias {alias} into the SII of all {count} slaves: give --force (or POS for one)")]
    AliasForce {
        /// The alias.
        alias: u16,
        /// The slaves.
        count: u16,
    },
    /// `sii-write`: an image IgH's checks refuse.
    #[error("{}: {error}; --force writes it anyway", path.display())]
    SiiImage {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        error: od::sii::ImageError,
    },
    /// `sii-write`: a file larger than any EEPROM.
    #[error("{}: more than {limit} bytes: no SII image (an ESC's EEPROM holds 4 Mbit at most)", path.display())]
    SiiTooLong {
        /// The file.
        path: PathBuf,
        /// The most an image has.
        limit: usize,
    },
    /// `sii-write`: an image larger than the slave's EEPROM.
    #[error(
        "{}: {bytes} bytes do not fit the EEPROM of slave {position}, {capacity} bytes (SII word \
         0x3E)", path.display()
    )]
    SiiTooLarge {
        /// The file.
        path: PathBuf,
        /// Its bytes.
        bytes: usize,
        /// The slave's position.
        position: u16,
        /// The EEPROM's bytes.
        capacity: usize,
    },
    /// A CANopen command with `--ethercat`.
    #[error(
        "`{command}` is a CANopen command: over EtherCAT (--ethercat) only read, write, dump, \
         apply, drive, slaves, states, sdos, pdos, sii-read, sii-write, reg-read, reg-write, \
         alias, xml, cstruct, foe-read and foe-write are available"
    )]
    CanopenOnly {
        /// The command's name.
        command: &'static str,
    },
}

#[cfg(test)]
mod tests {
    use super::UsageError::{self, *};
    use od::dict::Address;

    fn text(e: UsageError) -> String {
        e.to_string()
    }

    /// Each mistake's message is the one the user sees (the book and scripts compare them): those
    /// of nodes and NMT commands.
    #[test]
    fn node_and_command_messages() {
        assert_eq!(text(Node { node: 0 }), "node 0 is not 1 to 127");
        assert_eq!(
            text(NmtNode { node: 200 }),
            "node 200 is not 1 to 127 or all"
        );
        assert_eq!(
            text(NmtNodeText { text: "x".into() }),
            "node \"x\" is not 1 to 127 or all"
        );
        assert_eq!(
            text(NmtCommand {
                command: "go".into()
            }),
            "NMT command \"go\" is not start, stop, preop, reset or reset-comm"
        );
        for (count, slaves) in [(1, "1 slave"), (2, "2 slaves")] {
            let e = SlavePosition {
                position: 3,
                count,
                interface: "veth0".into(),
            };
            assert_eq!(
                text(e),
                format!("slave position 3 is not 1 to {count} (the chain on veth0 has {slaves})")
            );
        }
    }

    /// The messages of mistakes in an object, a type or a value.
    #[test]
    fn object_type_and_value_messages() {
        let addr = Address::new(0x2000, 0);
        assert_eq!(
            text(NameWithoutDescription { text: "foo".into() }),
            "object \"foo\" is not INDEX:SUB (e.g. 0x1018:01); names need --od"
        );
        assert_eq!(
            text(UnknownType { text: "u7".into() }),
            "type \"u7\" is not a CiA 309-3 type (b, i8–i64, u8–u64, x8–x64, r32, r64, vs, os, us, d, hex)"
        );
        assert_eq!(
            text(TypeNeeded),
            "give the type (e.g. u16), or a description with --od"
        );
        let access = |write, access| Access {
            address: addr,
            name: "Flags".into(),
            access,
            write,
        };
        assert_eq!(
            text(access(true, "ro")),
            format!("{addr} (Flags) is read-only (ro) in the description: not written")
        );
        assert_eq!(
            text(access(false, "wo")),
            format!("{addr} (Flags) is write-only (wo) in the description: not read")
        );
        assert_eq!(
            text(ValueRefused {
                address: addr,
                why: "too long".into()
            }),
            format!("{addr}: too long (not sent)")
        );
        let data_type = od::DataType::Unsigned16;
        assert_eq!(
            text(ValueMissing {
                address: addr,
                text: "u16".into(),
                data_type
            }),
            format!(
                "{addr}: the value is missing after the type u16 (write NODE OBJECT [TYPE] \
                 VALUE; {data_type} as TYPE)"
            )
        );
    }

    /// The messages of mistakes in files, options and where commands are run.
    #[test]
    fn file_and_option_messages() {
        let io = std::io::Error::other;
        assert_eq!(text(WriteArguments), "write NODE OBJECT [TYPE] VALUE");
        assert_eq!(
            text(NoDevice {
                what: "--od",
                path: "a.eds".into()
            }),
            "--od a.eds: no device in it"
        );
        assert_eq!(
            text(ListNeedsDescription),
            "list needs a description: --od FILE"
        );
        assert_eq!(
            text(DumpNeedsDescription),
            "dump needs the node's description: --od FILE"
        );
        assert_eq!(
            text(File {
                path: "a.bin".into(),
                error: io("gone")
            }),
            "a.bin: gone"
        );
        assert_eq!(text(Directory { path: "d".into() }), "d: a directory");
        assert_eq!(
            text(NotRegularFile { path: "f".into() }),
            "f: not a regular file"
        );
        assert_eq!(
            text(Log {
                name: "standard input".into(),
                error: io("bad")
            }),
            "standard input: bad"
        );
        assert_eq!(
            text(ListeningBus),
            "sdo-tool joins a bus: socketcan:IFACE or socketcand://HOST:PORT/CHANNEL"
        );
        assert_eq!(
            text(Listen {
                address: "127.0.0.1:1".parse().unwrap(),
                error: io("busy")
            }),
            "--listen 127.0.0.1:1: busy"
        );
        assert_eq!(
            text(EthercatOnly { command: "slaves" }),
            "`slaves` is an EtherCAT command: give --ethercat IFACE"
        );
        assert_eq!(
            text(CanopenOnly { command: "nmt" }),
            "`nmt` is a CANopen command: over EtherCAT (--ethercat) only read, write, dump, apply, \
             drive, slaves, states, sdos, pdos, sii-read, sii-write, reg-read, reg-write, alias, \
             xml, cstruct, foe-read and foe-write are available"
        );
        assert_eq!(
            text(OneSlave {
                command: "foe-read",
                how: "-p POS",
                interface: "veth0".into(),
                count: 2
            }),
            "`foe-read` takes one slave: the chain on veth0 has 2: give -p POS (1 = first)"
        );
        assert_eq!(text(CommandLine("bad".into())), "bad");
        assert_eq!(
            text(Capture(crate::link::CaptureError {
                path: "/x/c.pcapng".into(),
                source: io("gone")
            })),
            "--capture /x/c.pcapng: gone"
        );
        assert_eq!(
            text(NoCanInCapture {
                name: "e.pcapng".into(),
                interfaces: vec!["ecm0 (link type 1)".into(), "eth1 (link type 1)".into()]
            }),
            "e.pcapng: no SocketCAN interface in the capture (its interfaces: ecm0 (link type 1), \
             eth1 (link type 1)): decode names CAN frames only"
        );
        assert_eq!(
            text(NoCanInCapture {
                name: "e.pcapng".into(),
                interfaces: vec![]
            }),
            "e.pcapng: no SocketCAN interface in the capture (it describes none): decode names CAN \
             frames only"
        );
        assert_eq!(
            text(CaptureWithoutLink { command: "decode" }),
            "`decode` uses no bus and no EtherCAT interface: --capture has nothing to record"
        );
        assert_eq!(
            text(FoeStdinName),
            "foe-write - reads standard input: name the file on the slave with -o NAME"
        );
        assert_eq!(
            text(FoeJsonOutput),
            "foe-read --json: give -o FILE (the file's bytes and the JSON line would mix)"
        );
    }
}
