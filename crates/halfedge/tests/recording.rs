//! The recording switch (its own test program: the switch is process-wide).

use halfedge::recording::{self, Cut, Limits};
use halfedge::{shapes, DVec3};

#[test]
fn each_new_vertex_keeps_the_mesh_before_it_within_the_limits() {
    let mut mesh = shapes::lab_object("cube").unwrap();
    // Off: nothing is kept.
    mesh.new_vertex(DVec3::ZERO);
    assert!(recording::stop().frames.is_empty());

    recording::start(Limits {
        frames: 2,
        bytes: usize::MAX,
    });
    let before = mesh.num_vertices();
    for _ in 0..3 {
        mesh.new_vertex(DVec3::ONE);
        // Other elements take no frame.
        mesh.new_edge();
    }
    let r = recording::stop();
    assert_eq!(r.frames.len(), 2);
    assert_eq!(r.frames[0].num_vertices(), before);
    assert_eq!(r.frames[1].num_vertices(), before + 1);
    assert_eq!(r.frames[1].num_edges(), r.frames[0].num_edges() + 1);
    assert_eq!(r.cut, Some(Cut::Frames(2)));

    // The byte bound: the first frame fits, the second does not.
    let limit = recording::record_bytes(&mesh) + 1;
    recording::start(Limits {
        frames: 10,
        bytes: limit,
    });
    mesh.new_vertex(DVec3::ONE);
    mesh.new_vertex(DVec3::ONE);
    let r = recording::stop();
    assert_eq!((r.frames.len(), r.cut), (1, Some(Cut::Bytes(limit))));
}
