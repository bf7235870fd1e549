//! The EtherCAT part the ESI writer gives a description that has none (a CANopen description written
//! as an ESI): PDOs from the mapping objects and their default mapping, the four standard sync
//! managers, FMMUs and a CoE mailbox.

use crate::device::{
    CoeFlags, DeviceDescription, EsiRoot, EthercatInfo, Mailbox, Pdo, PdoEntry, SyncManager,
};
use crate::object::{Object, SubObject};
use crate::value::Value;

fn default_u64(sub: &SubObject) -> Option<u64> {
    let v = sub
        .default
        .as_ref()
        .map(|d| d.value.clone())
        .or_else(|| sub.current())?;
    match v {
        Value::Uint(u) => Some(u),
        Value::Int(i) => u64::try_from(i).ok(),
        Value::Bool(b) => Some(u64::from(b)),
        _ => None,
    }
}

fn derive_pdo(desc: &DeviceDescription, object: &Object, comm_base: u16, sm: u8) -> Pdo {
    let dict = &desc.dictionary;
    let count = object
        .subs
        .get(&0)
        .and_then(default_u64)
        .unwrap_or(0)
        .min(255) as u8;
    let mut entries = Vec::new();
    for s in 1..=count {
        let Some(raw) = object.subs.get(&s).and_then(default_u64) else {
            continue;
        };
        let raw = (raw & 0xFFFF_FFFF) as u32;
        if raw == 0 {
            continue;
        }
        let index = (raw >> 16) as u16;
        let sub = ((raw >> 8) & 0xFF) as u8;
        let bits = (raw & 0xFF) as u16;
        if (1..=7).contains(&index) {
            // CiA 301 dummy mapping: a gap.
            entries.push(PdoEntry {
                bit_len: bits,
                ..PdoEntry::default()
            });
            continue;
        }
        let (name, data_type) = match dict.entry(index, sub) {
            Ok(e) => {
                let name = if sub == 0 && e.name.is_empty() {
                    dict.object(index)
                        .map(|o| o.name.clone())
                        .unwrap_or_default()
                } else {
                    e.name.clone()
                };
                (name, e.data_type.esi_name(u32::from(bits)))
            }
            Err(_) => (String::new(), String::new()),
        };
        entries.push(PdoEntry {
            index,
            sub,
            bit_len: bits,
            name,
            data_type,
            ..PdoEntry::default()
        });
    }
    let n = object.index & 0x01FF;
    let valid = dict.entry(comm_base + n, 1).ok().and_then(default_u64);
    // Bit 31 of the COB-ID marks a CANopen PDO invalid (CiA 301 §7.5.2.35).
    let valid = !matches!(valid, Some(cob) if cob & 0x8000_0000 != 0);
    Pdo {
        index: object.index,
        name: object.name.clone(),
        fixed: !object
            .subs
            .get(&0)
            .is_some_and(|s| s.access.kind.writable()),
        sm: valid.then_some(sm),
        entries,
        ..Pdo::default()
    }
}

pub(super) fn derive_ethercat(desc: &DeviceDescription) -> EthercatInfo {
    let dict = &desc.dictionary;
    let rx: Vec<Pdo> = dict
        .objects()
        .filter(|o| (0x1600..=0x17FF).contains(&o.index))
        .map(|o| derive_pdo(desc, o, 0x1400, 2))
        .collect();
    let tx: Vec<Pdo> = dict
        .objects()
        .filter(|o| (0x1A00..=0x1BFF).contains(&o.index))
        .map(|o| derive_pdo(desc, o, 0x1800, 3))
        .collect();
    let bytes = |pdos: &[Pdo]| -> u16 {
        let bits: u32 = pdos
            .iter()
            .filter(|p| p.sm.is_some())
            .flat_map(|p| p.entries.iter())
            .map(|e| u32::from(e.bit_len))
            .sum();
        u16::try_from(bits.div_ceil(8)).unwrap_or(u16::MAX)
    };
    let out_bytes = bytes(&rx);
    let in_bytes = bytes(&tx);
    let pdo_config = rx.iter().chain(&tx).any(|p| !p.fixed);
    let mailbox = |kind: &str, start: u16, control: u8| SyncManager {
        kind: kind.to_string(),
        start_address: start,
        default_size: Some(128),
        min_size: None,
        max_size: None,
        control_byte: control,
        enable: 1,
        ..SyncManager::default()
    };
    let process = |kind: &str, start: u16, control: u8, size: u16| SyncManager {
        kind: kind.to_string(),
        start_address: start,
        default_size: (size > 0).then_some(size),
        min_size: None,
        max_size: None,
        control_byte: control,
        enable: u8::from(size > 0),
        ..SyncManager::default()
    };
    let id = &desc.identity;
    let group_type = if !id.order_code.is_empty() {
        id.order_code.clone()
    } else if !id.product_name.is_empty() {
        id.product_name.clone()
    } else {
        "Device".to_string()
    };
    EthercatInfo {
        group_type,
        fmmus: vec!["Outputs".into(), "Inputs".into(), "MBoxState".into()],
        sync_managers: vec![
            mailbox("MBoxOut", 0x1000, 0x26),
            mailbox("MBoxIn", 0x1080, 0x22),
            process("Outputs", 0x1100, 0x64, out_bytes),
            process("Inputs", 0x1400, 0x20, in_bytes),
        ],
        rx_pdos: rx,
        tx_pdos: tx,
        mailbox: Some(Mailbox {
            data_link_layer: true,
            coe: Some(CoeFlags {
                sdo_info: true,
                pdo_assign: false,
                pdo_config,
                pdo_upload: false,
                complete_access: false,
                segmented_sdo: true,
            }),
            foe: false,
            eoe: false,
            init_cmds: Vec::new(),
        }),
        op_modes: Vec::new(),
        eeprom: None,
        slots: None,
        modules: Default::default(),
        root: EsiRoot::EtherCatInfo,
    }
}
