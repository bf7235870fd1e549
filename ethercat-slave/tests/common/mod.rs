//! What the emulator's tests share.
#![allow(dead_code)]

/// The SMD23K-B of the SMD fixture ESI.
pub fn smd() -> od::DeviceDescription {
    let path = format!(
        "{}/../fixtures/smd/SMD23K-B_SMD24K.esi.xml",
        env!("CARGO_MANIFEST_DIR")
    );
    let (_, devices) = od::load::load(std::path::Path::new(&path)).unwrap();
    devices
        .into_iter()
        .find(|d| d.identity.order_code == "SMD23K-B")
        .expect("SMD23K-B in the fixture")
}
pub mod master;
