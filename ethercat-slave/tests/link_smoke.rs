mod common;
#[path = "common/link.rs"]
mod link;
#[test]
fn link_smoke() {
    let mut l = link::Link::up(&["--units", "2"]);
    assert!(l.running());
    let log = l.stop();
    assert!(log.contains("frames answered"), "{log}");
}
