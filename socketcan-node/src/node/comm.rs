//! Writes to the communication objects (CiA 301 §7.5.2): the rules each object sets on its values, the
//! commands among them (0x1003:00, 0x1010, 0x1011), and the node services a stored value changes. The
//! node is the SDO server's [`ObjectStore`] here.

use od::abort::AbortCode;
use od::dict::Address;
use od::hook;
use od::object::PdoMapping;
use od::sdo::store::{DownloadCapacity, ObjectStore};

use super::pdo::{
    self, Direction, PdoConfig, COB_EXTENDED, COB_INVALID, MAP_OFFSET, RPDO_COMM, TPDO_COMM,
};
use super::storage::{self, StorageRequest};
use super::{Core, Device, NmtState, NodeEvent, LOAD_SIGNATURE, SAVE_SIGNATURE};

impl<A: Device> Core<A> {
    /// True for the entries "save all parameters" keeps: writable, not mappable into PDOs (process
    /// data), and not the store/restore commands or the error history themselves.
    pub(super) fn storable(&self, index: u16, sub: u8) -> bool {
        if matches!(index, 0x1003 | 0x1010 | 0x1011) {
            return false;
        }
        self.dict
            .entry(index, sub)
            .is_ok_and(|e| e.access.kind.writable() && e.pdo == PdoMapping::None)
    }

    /// The entries "save all parameters" keeps, with their values.
    fn parameter_set(&self) -> Vec<(u16, u8, Vec<u8>)> {
        let mut out = Vec::new();
        for object in self.dict.objects() {
            for (&sub, entry) in &object.subs {
                if self.storable(object.index, sub) {
                    out.push((object.index, sub, entry.value.clone()));
                }
            }
        }
        out
    }

    /// Special rules of the communication objects, checked before a download is stored. `Ok(true)`: the
    /// download is complete without storing the value (commands). A COB-ID (SYNC, TIME, EMCY, PDO),
    /// PDO parameter or mapping entry written as the entry holds it is taken whatever the rules say
    /// (it changes nothing): a value the node reports, it takes back (`sdo-tool dump`, then `apply`;
    /// the mapping of a PDO whose COB-ID cannot be written, so that the PDO cannot be made invalid).
    fn check_download(&mut self, index: u16, sub: u8, data: &[u8]) -> Result<bool, AbortCode> {
        let unchanged = matches!(index, 0x1005 | 0x1012 | 0x1014 | RPDO_COMM..=0x15FF | TPDO_COMM..=0x19FF | 0x1600..=0x17FF | 0x1A00..=0x1BFF)
            && self.dict.entry(index, sub).is_ok_and(|e| e.value == data);
        if unchanged {
            return Ok(false);
        }
        let value = {
            let mut b = [0u8; 4];
            let n = data.len().min(4);
            b[..n].copy_from_slice(&data[..n]);
            u32::from_le_bytes(b)
        };
        match index {
            0x1003 if sub == 0 => {
                if value != 0 {
                    return Err(AbortCode::InvalidValue);
                }
                self.clear_history();
                return Ok(true);
            }
            0x1010 if sub >= 1 => {
                if value != SAVE_SIGNATURE {
                    return Err(AbortCode::CannotStore);
                }
                // The edge writes the set; the answer waits until it has (CiA 301 §7.5.2.13: the
                // answer confirms the save).
                let set = storage::encode(&self.parameter_set());
                self.request_storage(StorageRequest::Save(set.clone()));
                self.stored = Some(set);
                self.events.push_back(NodeEvent::Saved);
                return Ok(true);
            }
            0x1011 if sub >= 1 => {
                if value != LOAD_SIGNATURE {
                    return Err(AbortCode::CannotStore);
                }
                self.request_storage(StorageRequest::Clear);
                self.stored = None;
                self.events.push_back(NodeEvent::Restored);
                return Ok(true);
            }
            0x1005 | 0x1012 | 0x1014 => {
                let id = (value & 0x7FF) as u16;
                if value & COB_EXTENDED != 0 || (index == 0x1014 && pdo::restricted_id(id)) {
                    return Err(AbortCode::InvalidValue);
                }
            }
            RPDO_COMM..=0x15FF | TPDO_COMM..=0x19FF => self.check_pdo_comm(index, sub, value)?,
            0x1600..=0x17FF | 0x1A00..=0x1BFF => self.check_pdo_mapping(index, sub, value)?,
            _ => {}
        }
        Ok(false)
    }

    /// A PDO communication parameter (0x1400+, 0x1800+): COB-ID, transmission type, inhibit time.
    fn check_pdo_comm(&self, index: u16, sub: u8, value: u32) -> Result<(), AbortCode> {
        let n = usize::from(index & 0x1FF);
        let cfg = if index < TPDO_COMM {
            self.rpdos.get(n)
        } else {
            self.tpdos.get(n)
        };
        let valid = cfg.is_some_and(PdoConfig::valid);
        match sub {
            1 => {
                let id = (value & 0x7FF) as u16;
                if value & COB_EXTENDED != 0 || value & 0x1FFF_F800 != 0 || pdo::restricted_id(id) {
                    return Err(AbortCode::InvalidValue);
                }
                // The CAN-ID of a PDO that exists may not change (CiA 301 §7.5.2.35).
                let old = cfg.map_or(0, PdoConfig::cob_id);
                if valid && value & COB_INVALID == 0 && id != old {
                    return Err(AbortCode::InvalidValue);
                }
            }
            2 => {
                // CiA 301 §7.5.2.35/§7.5.2.37: 241–251 are reserved; 252 and 253 (remote request
                // only) exist for TPDOs, not RPDOs.
                let t = value as u8;
                if (241..=251).contains(&t) || (index < TPDO_COMM && (252..=253).contains(&t)) {
                    return Err(AbortCode::InvalidValue);
                }
            }
            3 if index >= TPDO_COMM && valid => return Err(AbortCode::InvalidValue),
            _ => {}
        }
        Ok(())
    }

    /// A PDO mapping parameter (0x1600+, 0x1A00+): changed only in Pre-operational while the PDO is
    /// invalid, entries only while sub-index 0 is 0 (the mapping procedure of CiA 301 §7.5.2.36).
    fn check_pdo_mapping(&self, index: u16, sub: u8, value: u32) -> Result<(), AbortCode> {
        let comm = index - MAP_OFFSET;
        let (dir, cfg) = if index < 0x1A00 {
            (Direction::Rx, self.rpdos.get(usize::from(comm - RPDO_COMM)))
        } else {
            (Direction::Tx, self.tpdos.get(usize::from(comm - TPDO_COMM)))
        };
        if self.state != NmtState::PreOperational {
            return Err(AbortCode::DeviceState);
        }
        if cfg.is_some_and(PdoConfig::valid) {
            return Err(AbortCode::ParameterIncompatible);
        }
        if sub == 0 {
            if value != 0 {
                pdo::check_count(&self.dict, dir, index, value as u8)?;
            }
        } else {
            if self.u32_at(index, 0).unwrap_or(0) != 0 {
                return Err(AbortCode::ParameterIncompatible);
            }
            pdo::check_entry(&self.dict, dir, value)?;
        }
        Ok(())
    }

    /// Effects of a stored download on the node's services.
    fn after_download(&mut self, index: u16) {
        let now = self.now;
        match index {
            0x1005 | 0x1006 => {
                self.sync_at = self.sync_period().map(|p| now + p);
                self.reload_listen();
            }
            0x1012 => {
                self.reload_time(now);
                self.reload_listen();
            }
            0x1016 => self.reload_consumer(),
            0x1017 => self.heartbeat_at = self.heartbeat_period().map(|p| now + p),
            0x1400..=0x1BFF => self.pdos_changed(),
            _ => {}
        }
    }
}

impl<A: Device> ObjectStore for Core<A> {
    fn upload(&mut self, mux: Address) -> Result<Vec<u8>, AbortCode> {
        hook::upload(&self.dict, &self.app, mux)
    }

    fn download_capacity(&self, mux: Address) -> Result<DownloadCapacity, AbortCode> {
        self.dict.download_capacity(mux)
    }

    fn download(&mut self, mux: Address, data: &[u8]) -> Result<(), AbortCode> {
        let (index, sub) = (mux.index, mux.sub);
        hook::check_download(&self.dict, &self.app, mux, data)?;
        if self.check_download(index, sub, data)? {
            return Ok(());
        }
        self.device_up_to(self.now);
        hook::store_download(&mut self.dict, &mut self.app, mux, data, self.now)?;
        self.after_download(index);
        Ok(())
    }
}
