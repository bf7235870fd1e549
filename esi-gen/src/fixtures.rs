//! The generated descriptions under `fixtures/`: what each is made from, and the check that the committed
//! files are what the generator makes.
//!
//! Sources (hand-written from the device documents): `fixtures/src/smd.esi.xml` (AMCI SMD23K-B and SMD24K)
//! and `fixtures/src/x67sm2436.xdd` (B&R X67SM2436 behind the X67BC4321). Identity values that the
//! documents do not publish come from `fixtures/identity.toml`.

use std::path::{Path, PathBuf};

use od::device::DeviceDescription;

use crate::{Error, IdentityFile};

fn load_source(
    root: &Path,
    name: &str,
    ids: &IdentityFile,
) -> Result<Vec<DeviceDescription>, Error> {
    let (_, mut devices) = od::load::load(&root.join("src").join(name))?;
    for d in &mut devices {
        ids.apply(d);
    }
    Ok(devices)
}

/// Every generated file under `root`, with the text it must have.
pub fn generate(root: &Path) -> Result<Vec<(PathBuf, String)>, Error> {
    let ids = IdentityFile::load(&root.join("identity.toml"))?;
    let mut files = Vec::new();
    let mut emit =
        |path: PathBuf, devs: &[DeviceDescription], write: fn(&[DeviceDescription]) -> String| {
            let name = path
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or_default()
                .to_string();
            let mut devs = devs.to_vec();
            for d in &mut devs {
                crate::stamp_file_info(d, &name);
            }
            files.push((path, write(&devs)));
        };
    let smd = load_source(root, "smd.esi.xml", &ids)?;
    emit(
        root.join("smd").join("SMD23K-B_SMD24K.esi.xml"),
        &smd,
        od::esi::write_all,
    );
    for dev in &smd {
        let name = crate::device_name(dev).to_string();
        let one = std::slice::from_ref(dev);
        emit(root.join("smd").join(format!("{name}.eds")), one, |d| {
            let mut d = d[0].clone();
            od::eds::complete_new_file(&mut d);
            od::eds::write_eds(&d)
        });
        emit(root.join("smd").join(format!("{name}.xdd")), one, |d| {
            od::xdd::write(&d[0])
        });
        emit(root.join("smd").join(format!("{name}.md")), one, |d| {
            od::doc::write(&d[0])
        });
    }
    for dev in load_source(root, "x67sm2436.xdd", &ids)? {
        let one = std::slice::from_ref(&dev);
        let dir = root.join("x67");
        emit(dir.join("X67SM2436.xdd"), one, |d| od::xdd::write(&d[0]));
        emit(dir.join("X67SM2436.eds"), one, |d| {
            let mut d = d[0].clone();
            od::eds::complete_new_file(&mut d);
            od::eds::write_eds(&d)
        });
        emit(dir.join("X67SM2436.esi.xml"), one, od::esi::write_all);
        emit(dir.join("X67SM2436.md"), one, |d| od::doc::write(&d[0]));
    }
    Ok(files)
}

/// The files whose bytes on disk differ from what the generator makes (or that are missing).
pub fn stale(files: &[(PathBuf, String)]) -> Vec<PathBuf> {
    files
        .iter()
        .filter(|(path, text)| std::fs::read(path).ok().as_deref() != Some(text.as_bytes()))
        .map(|(path, _)| path.clone())
        .collect()
}
