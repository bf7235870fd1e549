//! What the emulator's tests share.
#![allow(dead_code)]

pub mod master;

/// The SMD23K-B of the SMD fixture ESI.
pub fn smd() -> od::DeviceDescription {
    ethercat_slave::smd::description(ethercat_slave::smd::binding::Device::Smd23kB)
        .expect("the fixture")
}
