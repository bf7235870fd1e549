//! Typed views of the ESC registers the emulator implements (ETG.1000.4 §6, the ESC datasheet's
//! section II register tables): each is decoded from and encoded to the register bytes as the ESC
//! holds them, little-endian. The fields are the ones the ESC acts on; a view of a register with
//! bits the ESC does not implement says which ones it leaves out.

use super::al::AlState;

/// DL control (0x0100–0x0103, ETG.1000.4 DL control). Of it the ESC acts on the station alias
/// enable (bit 24); the rest (forwarding rule, loop control, RX FIFO size) is kept as it is.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DlControl(pub u32);

impl DlControl {
    /// Register address.
    pub const ADDRESS: u16 = 0x0100;
    /// Bit 24: configured-address datagrams may address the station alias (0x0012) too.
    const ALIAS: u32 = 1 << 24;

    /// The register from its 4 bytes.
    pub const fn decode(bytes: [u8; 4]) -> DlControl {
        DlControl(u32::from_le_bytes(bytes))
    }

    /// The register's 4 bytes.
    pub const fn encode(self) -> [u8; 4] {
        self.0.to_le_bytes()
    }

    /// Station alias addressing enabled (bit 24).
    pub const fn alias_enabled(self) -> bool {
        self.0 & Self::ALIAS != 0
    }
}

/// DL status (0x0110–0x0111, ETG.1000.4 DL status): the PDI and the state of the four ports.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DlStatus {
    /// Bit 0: the PDI is operational (the EEPROM was loaded).
    pub pdi_operational: bool,
    /// Bit 1: the DLS-user watchdog has not expired.
    pub pdi_watchdog: bool,
    /// Bit 2: enhanced link detection.
    pub enhanced_link_detection: bool,
    /// Bits 4–7: a physical link on port 0–3.
    pub link: [bool; 4],
    /// Bits 8, 10, 12, 14: port 0–3 closed (its loop closed).
    pub closed: [bool; 4],
    /// Bits 9, 11, 13, 15: communication on port 0–3.
    pub communication: [bool; 4],
}

impl DlStatus {
    /// Register address.
    pub const ADDRESS: u16 = 0x0110;

    /// The register from its 2 bytes (bit 3, reserved, is left out).
    pub fn decode(bytes: [u8; 2]) -> DlStatus {
        let v = u16::from_le_bytes(bytes);
        let bit = |n: u32| v & (1 << n) != 0;
        DlStatus {
            pdi_operational: bit(0),
            pdi_watchdog: bit(1),
            enhanced_link_detection: bit(2),
            link: std::array::from_fn(|p| bit(4 + p as u32)),
            closed: std::array::from_fn(|p| bit(8 + 2 * p as u32)),
            communication: std::array::from_fn(|p| bit(9 + 2 * p as u32)),
        }
    }

    /// The register's 2 bytes.
    pub fn encode(self) -> [u8; 2] {
        let mut v = u16::from(self.pdi_operational)
            | u16::from(self.pdi_watchdog) << 1
            | u16::from(self.enhanced_link_detection) << 2;
        for p in 0..4 {
            v |= u16::from(self.link[p]) << (4 + p);
            v |= u16::from(self.closed[p]) << (8 + 2 * p);
            v |= u16::from(self.communication[p]) << (9 + 2 * p);
        }
        v.to_le_bytes()
    }
}

/// AL control (0x0120–0x0121, ETG.1000.6 §6.4): the state the master requests.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AlControl {
    /// Bits 0–3 as written; [`AlControl::requested`] is the state they name.
    pub state: u8,
    /// Bit 4: the master acknowledges the error indication.
    pub acknowledge: bool,
    /// Bit 5: the master requests the device identification.
    pub device_identification: bool,
}

impl AlControl {
    /// Register address.
    pub const ADDRESS: u16 = 0x0120;

    /// The register from its 2 bytes (bits 6–15, reserved, are left out).
    pub const fn decode(bytes: [u8; 2]) -> AlControl {
        AlControl {
            state: bytes[0] & 0x0F,
            acknowledge: bytes[0] & 0x10 != 0,
            device_identification: bytes[0] & 0x20 != 0,
        }
    }

    /// The register's 2 bytes.
    pub const fn encode(self) -> [u8; 2] {
        let acknowledge = if self.acknowledge { 0x10 } else { 0 };
        let identification = if self.device_identification { 0x20 } else { 0 };
        [(self.state & 0x0F) | acknowledge | identification, 0]
    }

    /// The requested state, or `None` when the state bits name none.
    pub const fn requested(self) -> Option<AlState> {
        AlState::from_bits(self.state)
    }
}

/// AL status (0x0130–0x0131, ETG.1000.6 §6.4): the state the slave is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AlStatus {
    /// Bits 0–3. Only the ESC writes them, always with a state; bits that name none decode as
    /// Init.
    pub state: AlState,
    /// Bit 4: the error indication (the last request was refused, AL status code 0x0134 says why).
    pub error: bool,
}

impl AlStatus {
    /// Register address.
    pub const ADDRESS: u16 = 0x0130;

    /// The register from its 2 bytes (bit 5 and bits 6–15 are left out).
    pub const fn decode(bytes: [u8; 2]) -> AlStatus {
        let state = match AlState::from_bits(bytes[0]) {
            Some(state) => state,
            None => AlState::Init,
        };
        AlStatus {
            state,
            error: bytes[0] & 0x10 != 0,
        }
    }

    /// The register's 2 bytes.
    pub const fn encode(self) -> [u8; 2] {
        let error = if self.error { 0x10 } else { 0 };
        [self.state.bits() | error, 0]
    }
}

/// An EEPROM command (EEPROM control/status bits 8–10).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EepromCommand {
    /// 000: no command.
    Idle,
    /// 001: read 8 bytes from the word address into the data register.
    Read,
    /// 010: write one word of the data register at the word address.
    Write,
    /// 100: reload the ESC configuration from the EEPROM.
    Reload,
    /// Any other value (the ESC does nothing).
    Other(u8),
}

/// EEPROM control/status (0x0502–0x0503, ETG.1000.4 §6.4): the master's command and the ESC's
/// answer to it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EepromControl {
    /// Bit 0: write access enabled (valid for the write command in the same access).
    pub write_enable: bool,
    /// Bit 6: a read command reads 8 bytes (0: 4 bytes).
    pub read_8_bytes: bool,
    /// Bits 8–10: the command.
    pub command: EepromCommand,
    /// Bit 13: the last command failed (a write not enabled, or beyond the EEPROM).
    pub command_error: bool,
}

impl EepromControl {
    /// Register address.
    pub const ADDRESS: u16 = 0x0502;

    /// The register from its 2 bytes (the bits the ESC does not implement are left out).
    pub const fn decode(bytes: [u8; 2]) -> EepromControl {
        let v = u16::from_le_bytes(bytes);
        let command = match (v >> 8) & 0x07 {
            0 => EepromCommand::Idle,
            1 => EepromCommand::Read,
            2 => EepromCommand::Write,
            4 => EepromCommand::Reload,
            other => EepromCommand::Other(other as u8),
        };
        EepromControl {
            write_enable: v & 0x0001 != 0,
            read_8_bytes: v & 0x0040 != 0,
            command,
            command_error: v & 0x2000 != 0,
        }
    }

    /// The register's 2 bytes.
    pub const fn encode(self) -> [u8; 2] {
        let command: u16 = match self.command {
            EepromCommand::Idle => 0,
            EepromCommand::Read => 1,
            EepromCommand::Write => 2,
            EepromCommand::Reload => 4,
            EepromCommand::Other(c) => (c & 0x07) as u16,
        };
        let v = (self.write_enable as u16)
            | (self.read_8_bytes as u16) << 6
            | command << 8
            | (self.command_error as u16) << 13;
        v.to_le_bytes()
    }
}

/// The registers of one FMMU (0x0600 + 16·n, 16 bytes, ETG.1000.4 Table 57).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FmmuRegisters {
    /// Bytes 0–3: logical start address.
    pub logical_start: u32,
    /// Bytes 4–5: length in bytes.
    pub len: u16,
    /// Byte 6: logical start bit (bits 0–2).
    pub logical_start_bit: u8,
    /// Byte 7: logical stop bit (bits 0–2).
    pub logical_stop_bit: u8,
    /// Bytes 8–9: physical start address.
    pub physical_start: u16,
    /// Byte 10: physical start bit (bits 0–2).
    pub physical_start_bit: u8,
    /// Byte 11 bit 0: the FMMU maps reads (LRD, LRW).
    pub read: bool,
    /// Byte 11 bit 1: the FMMU maps writes (LWR, LRW).
    pub write: bool,
    /// Byte 12 bit 0: activated.
    pub active: bool,
}

impl FmmuRegisters {
    /// Bytes of one FMMU's registers.
    pub const LEN: usize = 16;

    /// The registers from their 16 bytes (bytes 13–15 and the unused bits are left out).
    pub const fn decode(r: [u8; 16]) -> FmmuRegisters {
        FmmuRegisters {
            logical_start: u32::from_le_bytes([r[0], r[1], r[2], r[3]]),
            len: u16::from_le_bytes([r[4], r[5]]),
            logical_start_bit: r[6] & 0x07,
            logical_stop_bit: r[7] & 0x07,
            physical_start: u16::from_le_bytes([r[8], r[9]]),
            physical_start_bit: r[10] & 0x07,
            read: r[11] & 0x01 != 0,
            write: r[11] & 0x02 != 0,
            active: r[12] & 0x01 != 0,
        }
    }

    /// The registers' 16 bytes.
    pub const fn encode(self) -> [u8; 16] {
        let l = self.logical_start.to_le_bytes();
        let n = self.len.to_le_bytes();
        let p = self.physical_start.to_le_bytes();
        [
            l[0],
            l[1],
            l[2],
            l[3],
            n[0],
            n[1],
            self.logical_start_bit & 0x07,
            self.logical_stop_bit & 0x07,
            p[0],
            p[1],
            self.physical_start_bit & 0x07,
            self.read as u8 | (self.write as u8) << 1,
            self.active as u8,
            0,
            0,
            0,
        ]
    }
}

/// The registers of one SyncManager (0x0800 + 8·n, 8 bytes, ETG.1000.4 §6.7).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SyncManagerRegisters {
    /// Bytes 0–1: physical start address.
    pub start: u16,
    /// Bytes 2–3: length in bytes.
    pub len: u16,
    /// Byte 4: control ([`SmControl`]).
    pub control: u8,
    /// Byte 5: status (the ESC's): bit 0 write event ([`super::sm::WRITE_EVENT`]), bit 1 read
    /// event, bit 3 mailbox full ([`super::sm::MAILBOX_FULL`]).
    pub status: u8,
    /// Byte 6: activate: bit 0 enable, bit 1 repeat request.
    pub activate: u8,
    /// Byte 7: PDI control (the application's): bit 0 deactivate, bit 1 repeat acknowledge.
    pub pdi_control: u8,
}

impl SyncManagerRegisters {
    /// Bytes of one SyncManager's registers.
    pub const LEN: usize = 8;
    /// Offset of the status byte.
    pub const STATUS: u16 = 5;
    /// Offset of the PDI control byte.
    pub const PDI_CONTROL: u16 = 7;

    /// The registers from their 8 bytes.
    pub const fn decode(r: [u8; 8]) -> SyncManagerRegisters {
        SyncManagerRegisters {
            start: u16::from_le_bytes([r[0], r[1]]),
            len: u16::from_le_bytes([r[2], r[3]]),
            control: r[4],
            status: r[5],
            activate: r[6],
            pdi_control: r[7],
        }
    }

    /// The registers' 8 bytes.
    pub const fn encode(self) -> [u8; 8] {
        let s = self.start.to_le_bytes();
        let n = self.len.to_le_bytes();
        [
            s[0],
            s[1],
            n[0],
            n[1],
            self.control,
            self.status,
            self.activate,
            self.pdi_control,
        ]
    }

    /// Activate bit 0: the master enabled it.
    pub const fn activated(self) -> bool {
        self.activate & 0x01 != 0
    }

    /// Activate bit 1: the master's repeat request.
    pub const fn repeat_request(self) -> bool {
        self.activate & 0x02 != 0
    }

    /// PDI control bit 0: the application deactivated it.
    pub const fn pdi_deactivated(self) -> bool {
        self.pdi_control & 0x01 != 0
    }

    /// PDI control bit 1: the application's repeat acknowledge.
    pub const fn repeat_ack(self) -> bool {
        self.pdi_control & 0x02 != 0
    }

    /// Enabled: activated by the master and not deactivated by the application.
    pub const fn enabled(self) -> bool {
        self.activated() && !self.pdi_deactivated()
    }

    /// The configuration the master sets (start, length, control and the enable bit): what, when
    /// it changes, empties the SyncManager's mailbox.
    pub const fn configuration(self) -> (u16, u16, u8, bool) {
        (self.start, self.len, self.control, self.activated())
    }
}

/// A SyncManager's control byte (byte 4 of its registers, ETG.1000.4 §6.7).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SmControl(pub u8);

impl SmControl {
    /// Bits 0–1 = 10: mailbox mode (one buffer); 00 is buffered mode (three buffers).
    pub const fn is_mailbox(self) -> bool {
        self.0 & 0x03 == 0x02
    }

    /// Bits 2–3 = 01: the master writes the buffer (00: the master reads it).
    pub const fn master_writes(self) -> bool {
        (self.0 >> 2) & 0x03 == 0x01
    }

    /// Bit 6: the SyncManager watchdog is enabled.
    pub const fn watchdog(self) -> bool {
        self.0 & 0x40 != 0
    }
}

/// Sync activation (0x0981, ETG.1000.4 §6.8 and the ESC datasheet): which SYNC signals run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SyncActivation {
    /// Bit 0: cyclic operation.
    pub cyclic: bool,
    /// Bit 1: SYNC0 generated.
    pub sync0: bool,
    /// Bit 2: SYNC1 generated.
    pub sync1: bool,
}

impl SyncActivation {
    /// Register address.
    pub const ADDRESS: u16 = 0x0981;

    /// The register from its byte (bits 3–7 are left out).
    pub const fn decode(byte: u8) -> SyncActivation {
        SyncActivation {
            cyclic: byte & 0x01 != 0,
            sync0: byte & 0x02 != 0,
            sync1: byte & 0x04 != 0,
        }
    }

    /// The register's byte.
    pub const fn encode(self) -> u8 {
        self.cyclic as u8 | (self.sync0 as u8) << 1 | (self.sync1 as u8) << 2
    }

    /// SYNC0 events are generated: cyclic operation and SYNC0 activated.
    pub const fn sync0_running(self) -> bool {
        self.cyclic && self.sync0
    }
}

/// System time difference (0x092C–0x092F, ETG.1000.4 §6.8): how far the ESC's copy of the system
/// time is from the time the master last wrote to the system time register.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SystemTimeDifference {
    /// Bits 0–30: the difference in ns.
    pub magnitude: u32,
    /// Bit 31: the local copy is smaller than the time written.
    pub local_smaller: bool,
}

impl SystemTimeDifference {
    /// Register address.
    pub const ADDRESS: u16 = 0x092C;
    /// The largest magnitude the register holds.
    pub const MAX: u32 = 0x7FFF_FFFF;

    /// The difference of `local` to the `received` time, the magnitude at most [`Self::MAX`].
    pub fn between(local: u64, received: u64) -> SystemTimeDifference {
        let (magnitude, local_smaller) = if local >= received {
            (local - received, false)
        } else {
            (received - local, true)
        };
        SystemTimeDifference {
            magnitude: magnitude.min(u64::from(Self::MAX)) as u32,
            local_smaller,
        }
    }

    /// The register from its 4 bytes.
    pub const fn decode(bytes: [u8; 4]) -> SystemTimeDifference {
        let v = u32::from_le_bytes(bytes);
        SystemTimeDifference {
            magnitude: v & Self::MAX,
            local_smaller: v & (1 << 31) != 0,
        }
    }

    /// The register's 4 bytes.
    pub const fn encode(self) -> [u8; 4] {
        let sign = if self.local_smaller { 1 << 31 } else { 0 };
        ((self.magnitude & Self::MAX) | sign).to_le_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// DL status as a slave in the middle of a chain and at its end reports it: PDI operational,
    /// link and communication on port 0, ports 2 and 3 closed; port 1 with link and communication
    /// where a slave follows, closed at the end. Bits 0, 4, 5, 9, 11, 12, 14 = 0x5A31 and bits 0,
    /// 4, 9, 10, 12, 14 = 0x5611.
    #[test]
    fn dl_status_bytes() {
        let middle = DlStatus {
            pdi_operational: true,
            link: [true, true, false, false],
            closed: [false, false, true, true],
            communication: [true, true, false, false],
            ..DlStatus::default()
        };
        assert_eq!(middle.encode(), [0x31, 0x5A]);
        assert_eq!(DlStatus::decode([0x31, 0x5A]), middle);
        let end = DlStatus {
            link: [true, false, false, false],
            closed: [false, true, true, true],
            communication: [true, false, false, false],
            ..middle
        };
        assert_eq!(end.encode(), [0x11, 0x56]);
        assert_eq!(DlStatus::decode([0x11, 0x56]), end);
        let all = DlStatus {
            pdi_operational: true,
            pdi_watchdog: true,
            enhanced_link_detection: true,
            link: [true; 4],
            closed: [true; 4],
            communication: [true; 4],
        };
        // Bit 3 is reserved.
        assert_eq!(all.encode(), [0xF7, 0xFF]);
        assert_eq!(DlStatus::decode([0xFF, 0xFF]), all);
    }

    /// DL control: bit 24 is byte 0x0103 bit 0; the other bits stay as they are.
    #[test]
    fn dl_control_alias_bit() {
        let c = DlControl::decode([0x01, 0x00, 0x00, 0x01]);
        assert!(c.alias_enabled());
        assert_eq!(c, DlControl(0x0100_0001));
        assert_eq!(c.encode(), [0x01, 0x00, 0x00, 0x01]);
        assert!(!DlControl::decode([0xFF, 0xFF, 0xFF, 0xFE]).alias_enabled());
    }

    /// AL control: Op (8) with the acknowledge (bit 4) is 0x18; Safe-Op with the device
    /// identification (bit 5) is 0x24; state bits 0x0F name no state.
    #[test]
    fn al_control_bytes() {
        let op_ack = AlControl {
            state: 8,
            acknowledge: true,
            device_identification: false,
        };
        assert_eq!(op_ack.encode(), [0x18, 0x00]);
        assert_eq!(AlControl::decode([0x18, 0x00]), op_ack);
        assert_eq!(op_ack.requested(), Some(AlState::Op));
        let safe_op_id = AlControl::decode([0x24, 0xFF]);
        assert_eq!(
            safe_op_id,
            AlControl {
                state: 4,
                acknowledge: false,
                device_identification: true,
            }
        );
        assert_eq!(safe_op_id.encode(), [0x24, 0x00]);
        assert_eq!(AlControl::decode([0x0F, 0]).requested(), None);
        assert_eq!(
            AlControl::decode([0x02, 0]).requested(),
            Some(AlState::PreOp)
        );
    }

    /// AL status: Pre-Op with the error indication is 0x12; Op without is 0x08; bits naming no
    /// state decode as Init.
    #[test]
    fn al_status_bytes() {
        let refused = AlStatus {
            state: AlState::PreOp,
            error: true,
        };
        assert_eq!(refused.encode(), [0x12, 0x00]);
        assert_eq!(AlStatus::decode([0x12, 0x00]), refused);
        let op = AlStatus {
            state: AlState::Op,
            error: false,
        };
        assert_eq!(op.encode(), [0x08, 0x00]);
        assert_eq!(AlStatus::decode([0x08, 0x00]), op);
        assert_eq!(
            AlStatus::decode([0x17, 0x00]),
            AlStatus {
                state: AlState::Init,
                error: true,
            }
        );
    }

    /// EEPROM control/status: a read command with write enable is 0x0101; the ESC's answers are
    /// 0x0040 (8 bytes read at once) and 0x2040 (and a command error).
    #[test]
    fn eeprom_control_bytes() {
        let read = EepromControl::decode([0x01, 0x01]);
        assert_eq!(
            read,
            EepromControl {
                write_enable: true,
                read_8_bytes: false,
                command: EepromCommand::Read,
                command_error: false,
            }
        );
        assert_eq!(read.encode(), [0x01, 0x01]);
        for (bytes, command) in [
            ([0x00, 0x00], EepromCommand::Idle),
            ([0x00, 0x02], EepromCommand::Write),
            ([0x00, 0x04], EepromCommand::Reload),
            ([0x00, 0x03], EepromCommand::Other(3)),
            ([0x00, 0xFF], EepromCommand::Other(7)),
        ] {
            assert_eq!(
                EepromControl::decode(bytes).command,
                command,
                "{bytes:02X?}"
            );
        }
        let answer = |command_error| EepromControl {
            write_enable: false,
            read_8_bytes: true,
            command: EepromCommand::Idle,
            command_error,
        };
        assert_eq!(answer(false).encode(), [0x40, 0x00]);
        assert_eq!(answer(true).encode(), [0x40, 0x20]);
        assert_eq!(EepromControl::decode([0x40, 0x20]), answer(true));
    }

    /// An FMMU mapping logical 0x0001_0000, 6 bytes (bits 0 to 7) onto 0x1100 for reads and
    /// writes, active: the bytes of ETG.1000.4 Table 57 field by field.
    #[test]
    fn fmmu_bytes() {
        let bytes = [
            0x00, 0x00, 0x01, 0x00, 0x06, 0x00, 0x00, 0x07, 0x00, 0x11, 0x00, 0x03, 0x01, 0x00,
            0x00, 0x00,
        ];
        let f = FmmuRegisters {
            logical_start: 0x0001_0000,
            len: 6,
            logical_start_bit: 0,
            logical_stop_bit: 7,
            physical_start: 0x1100,
            physical_start_bit: 0,
            read: true,
            write: true,
            active: true,
        };
        assert_eq!(FmmuRegisters::decode(bytes), f);
        assert_eq!(f.encode(), bytes);
        // Writes only, bit offsets 3 / 5 / 1, not active; the reserved bytes do not decode.
        let g = FmmuRegisters::decode([
            0x78, 0x56, 0x34, 0x12, 0x34, 0x12, 0xFB, 0x05, 0xCD, 0xAB, 0x01, 0x02, 0xFE, 0xAA,
            0xBB, 0xCC,
        ]);
        assert_eq!(
            g,
            FmmuRegisters {
                logical_start: 0x1234_5678,
                len: 0x1234,
                logical_start_bit: 3,
                logical_stop_bit: 5,
                physical_start: 0xABCD,
                physical_start_bit: 1,
                read: false,
                write: true,
                active: false,
            }
        );
        assert_eq!(
            g.encode(),
            [
                0x78, 0x56, 0x34, 0x12, 0x34, 0x12, 0x03, 0x05, 0xCD, 0xAB, 0x01, 0x02, 0x00, 0x00,
                0x00, 0x00
            ]
        );
    }

    /// SM0 as a master sets a write mailbox: 0x1000, 128 bytes, control 0x26 (mailbox, written
    /// by the master, ECAT interrupt), activated; status mailbox full; PDI control 0.
    #[test]
    fn sync_manager_bytes() {
        let bytes = [0x00, 0x10, 0x80, 0x00, 0x26, 0x08, 0x01, 0x00];
        let sm = SyncManagerRegisters {
            start: 0x1000,
            len: 128,
            control: 0x26,
            status: 0x08,
            activate: 0x01,
            pdi_control: 0x00,
        };
        assert_eq!(SyncManagerRegisters::decode(bytes), sm);
        assert_eq!(sm.encode(), bytes);
        assert!(sm.activated() && sm.enabled() && !sm.repeat_request());
        assert_eq!(sm.configuration(), (0x1000, 128, 0x26, true));
        let control = SmControl(sm.control);
        assert!(control.is_mailbox() && control.master_writes() && !control.watchdog());
        // SM2, outputs: 0x1100, 4 bytes, 0x64 (buffered, written, watchdog), repeat request 1,
        // deactivated by the PDI and repeat acknowledged.
        let sm2 = SyncManagerRegisters::decode([0x00, 0x11, 0x04, 0x00, 0x64, 0x00, 0x03, 0x03]);
        assert!(sm2.activated() && sm2.repeat_request());
        assert!(sm2.pdi_deactivated() && sm2.repeat_ack() && !sm2.enabled());
        let control = SmControl(sm2.control);
        assert!(!control.is_mailbox() && control.master_writes() && control.watchdog());
        // SM1, read by the master (0x22), and SM3 inputs (0x20).
        assert!(SmControl(0x22).is_mailbox() && !SmControl(0x22).master_writes());
        assert!(!SmControl(0x20).is_mailbox() && !SmControl(0x20).master_writes());
        assert!(!SmControl(0x2B).master_writes()); // direction 10: reserved
    }

    /// Sync activation: 0x03 runs SYNC0, 0x01 or 0x02 alone do not; SYNC1 is bit 2.
    #[test]
    fn sync_activation_bytes() {
        let a = SyncActivation::decode(0x03);
        assert_eq!(
            a,
            SyncActivation {
                cyclic: true,
                sync0: true,
                sync1: false,
            }
        );
        assert!(a.sync0_running());
        assert_eq!(a.encode(), 0x03);
        assert!(!SyncActivation::decode(0x01).sync0_running());
        assert!(!SyncActivation::decode(0x02).sync0_running());
        assert!(SyncActivation::decode(0xFF).sync1);
        assert_eq!(SyncActivation::decode(0xFF).encode(), 0x07);
    }

    /// System time difference: 1000 ns ahead is 0x0000_03E8; 1000 ns behind sets bit 31
    /// (0x8000_03E8); more than 2^31 − 1 ns stays at 0x7FFF_FFFF.
    #[test]
    fn system_time_difference_bytes() {
        let ahead = SystemTimeDifference::between(5_000, 4_000);
        assert_eq!(ahead.encode(), [0xE8, 0x03, 0x00, 0x00]);
        let behind = SystemTimeDifference::between(4_000, 5_000);
        assert_eq!(behind.encode(), [0xE8, 0x03, 0x00, 0x80]);
        assert_eq!(
            SystemTimeDifference::decode([0xE8, 0x03, 0x00, 0x80]),
            behind
        );
        let far = SystemTimeDifference::between(0, 1 << 40);
        assert_eq!(far.encode(), [0xFF, 0xFF, 0xFF, 0xFF]);
        let far = SystemTimeDifference::between(1 << 40, 0);
        assert_eq!(far.encode(), [0xFF, 0xFF, 0xFF, 0x7F]);
    }
}
