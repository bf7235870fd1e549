//! Every device of every ESI of the corpus beside the checkout: made ready to run or refused in one
//! line, never a panic; each one that runs answers a master's start-up: Pre-Op with its mailbox,
//! Safe-Op and Op with its own process images, and one LRW whose working counter counts the unit
//! once for reading its inputs and twice for writing its outputs (ETG.1000.4 §5.4.3).

#[path = "common/node.rs"]
mod node;

use std::time::Duration;

use ethercat_slave::generic::Template;
use ethercat_slave::master::Layout;
use node::*;

#[test]
fn every_corpus_device_runs_or_is_refused_in_one_line() {
    let dir = root().join("../shared/corpus/esi");
    assert!(
        dir.is_dir(),
        "{} is missing: the corpus beside the checkout",
        dir.display()
    );
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let (mut ran, mut refused, mut bad_mailbox) = (0, 0, 0);
    for path in files {
        let bytes = std::fs::read(&path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let Ok(devices) = od::esi::read_all(&bytes, &name) else {
            continue;
        };
        for desc in devices {
            let device = format!("{name} {}", ethercat_slave::generic::device_name(&desc));
            // A mailbox SyncManager whose ESI control byte is not in mailbox mode (bits 0–1 = 10)
            // cannot pass Init → Pre-Op: 0x0016, invalid mailbox configuration.
            let mailbox_mode = desc.ethercat.as_ref().is_none_or(|ec| {
                ec.sync_managers
                    .iter()
                    .filter(|s| s.kind.starts_with("MBox"))
                    .all(|s| s.control_byte & 0x03 == 0x02)
            });
            let t = match Template::new(desc, None) {
                Ok(t) => t,
                Err(e) => {
                    let line = e.to_string();
                    assert_eq!(line.lines().count(), 1, "{device}: {line}");
                    assert!(
                        line.starts_with(&device[name.len() + 1..]),
                        "{device}: {line}"
                    );
                    refused += 1;
                    continue;
                }
            };
            let layout = Layout::of(&t);
            let mut c = chain(&[(&t, 1)]);
            configure(&mut c, std::slice::from_ref(&layout));
            assert_eq!(brd(&mut c, 0x0130, 2).wkc, 1, "{device}");
            request(&mut c, 0x02);
            c.cycle(Duration::from_millis(1));
            if !mailbox_mode {
                assert_eq!(al(&mut c, 0), (0x11, 0x0016), "{device}");
                bad_mailbox += 1;
                continue;
            }
            assert_eq!(al(&mut c, 0), (0x02, 0), "{device}: Pre-Op");
            request(&mut c, 0x04);
            assert_eq!(al(&mut c, 0), (0x04, 0), "{device}: Safe-Op");
            let (o, i) = layout.lengths();
            // A cycle puts the first inputs in: an input SyncManager in mailbox mode (an AX2000's
            // control byte 0x22) is read only while full.
            c.cycle(Duration::from_millis(1));
            let (wkc, _) = lrw(&mut c, std::slice::from_ref(&layout), &[vec![0; o]]);
            let expected = u16::from(i > 0) + 2 * u16::from(o > 0);
            assert_eq!(wkc, expected, "{device}: {o} output and {i} input bytes");
            request(&mut c, 0x08);
            assert_eq!(al(&mut c, 0), (0x08, 0), "{device}: Op");
            ran += 1;
        }
    }
    eprintln!("{ran} devices ran, {bad_mailbox} refused Pre-Op, {refused} refused");
    // The corpus has hundreds of devices; a reader that found none would pass the loop above.
    assert!(ran > 500, "only {ran} devices ran");
}
