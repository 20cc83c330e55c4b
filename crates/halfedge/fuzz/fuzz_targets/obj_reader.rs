//! Fuzzes the OBJ reader: any bytes either fail with a message naming a
//! line (or the whole file, when empty) or give a mesh that validates.
#![no_main]

use halfedge::{Mesh, MeshError};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Mesh::read_obj_str(text, "fuzz.obj") {
        Ok((mesh, _)) => {
            if let Err(bad) = mesh.validate() {
                panic!("accepted a mesh that does not validate: {bad}");
            }
            // What the writer makes, the reader takes back unchanged.
            let again = Mesh::from_obj_str(&mesh.to_obj_string(), "again.obj")
                .expect("the writer's output reads back");
            assert_eq!(again.to_faces(), mesh.to_faces());
        }
        Err(MeshError::Obj { line, message, .. }) => {
            assert!(line >= 1 || message.contains("empty"), "{message}");
        }
        Err(other) => panic!("a bare error from the reader: {other:?}"),
    }
});
