//! The OBJ reader never skips anything silently: what the lab ignores is a
//! warning with file, line and statement; anything else is an error.

use halfedge::obj::{self, ObjWarning};
use halfedge::Mesh;

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

fn read(text: &str) -> (Mesh, Vec<ObjWarning>) {
    Mesh::read_obj_str(text, "t.obj").unwrap_or_else(|e| panic!("{e}\nfor:\n{text}"))
}

fn read_err(text: &str) -> String {
    match Mesh::read_obj_str(text, "t.obj") {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn ignored_statements_are_warnings_with_file_line_and_statement() {
    let text = "mtllib box.mtl\no box\nv 0 0 0\nv 1 0 0 # x\nv 0 1 0\nvt 0 0\nvn 0 0 1\n\
                g side\ns 1\nusemtl red\nf 1/1/1 2/1/1 3/1/1\nl 1 2\np 3\nvn 0 0 -1\n";
    let (mesh, warnings) = read(text);
    assert_eq!(mesh.num_real_faces(), 1);
    let lines: Vec<String> = warnings.iter().map(ToString::to_string).collect();
    assert_eq!(
        lines,
        [
            "t.obj:1: warning: ignored `mtllib` (the lab reads only vertex positions and faces): `mtllib box.mtl`",
            "t.obj:2: warning: ignored `o` (the lab reads only vertex positions and faces): `o box`",
            "t.obj:6: warning: ignored `vt` (the lab reads only vertex positions and faces): `vt 0 0`",
            "t.obj:7: warning: ignored `vn` (the lab reads only vertex positions and faces): `vn 0 0 1`",
            "t.obj:8: warning: ignored `g` (the lab reads only vertex positions and faces): `g side`",
            "t.obj:9: warning: ignored `s` (the lab reads only vertex positions and faces): `s 1`",
            "t.obj:10: warning: ignored `usemtl` (the lab reads only vertex positions and faces): `usemtl red`",
            "t.obj:12: warning: ignored `l` (the lab reads only vertex positions and faces): `l 1 2`",
            "t.obj:13: warning: ignored `p` (the lab reads only vertex positions and faces): `p 3`",
            "t.obj:14: warning: ignored `vn` (the lab reads only vertex positions and faces): `vn 0 0 -1`",
        ]
    );
    assert_eq!(
        obj::summary(&warnings).unwrap(),
        "t.obj: ignored 1 `mtllib`, 1 `o`, 1 `vt`, 2 `vn`, 1 `g`, 1 `s`, 1 `usemtl`, 1 `l`, 1 `p` \
         (the lab reads only vertex positions and faces)"
    );
}

#[test]
fn a_plain_file_has_no_warnings_and_no_summary() {
    let (_, warnings) = read(&format!("# just a triangle\n{TRI}f 1 2 3\n"));
    assert!(warnings.is_empty());
    assert_eq!(obj::summary(&warnings), None);
    for name in halfedge::shapes::LAB_OBJECTS {
        let text = halfedge::shapes::lab_object_obj(name).unwrap();
        assert!(read(text).1.is_empty(), "{name}");
    }
}

#[test]
fn vertex_weights_and_colours_are_dropped_with_a_warning() {
    let (mesh, warnings) = read("v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(mesh.positions()[1].x, 1.0);
    let dropped: Vec<(usize, &str)> = warnings
        .iter()
        .map(|w| (w.line, w.dropped.as_str()))
        .collect();
    assert_eq!(dropped, [(1, "vertex weight"), (2, "vertex colour")]);
    assert!(read_err("v 0 0 0 1 2\n").starts_with(
        "t.obj:1: a vertex needs three coordinates (four with a weight, six with a colour), found 5"
    ));
    assert_eq!(
        read_err("v 0 0 0 red\n"),
        "t.obj:1: `red` is not a number: `v 0 0 0 red`"
    );
}

#[test]
fn a_capital_f_is_an_error_not_a_hole() {
    // Once skipped: the cube lost a face and was subdivided with boundary rules.
    let mut cube = halfedge::shapes::lab_object_obj("cube")
        .unwrap()
        .to_string();
    let at = cube.find("\nf ").unwrap() + 1;
    cube.replace_range(at..at + 1, "F");
    let line = cube[..at].matches('\n').count() + 1;
    let e = read_err(&cube);
    assert!(
        e.starts_with(&format!(
            "t.obj:{line}: `F` is not an OBJ statement (OBJ keywords are lower case: did you mean `f`?): `F "
        )),
        "{e}"
    );
}

#[test]
fn unknown_statements_are_errors_with_their_line() {
    assert_eq!(
        read_err(&format!("{TRI}face 1 2 3\n")),
        "t.obj:4: `face` is not an OBJ statement: `face 1 2 3`"
    );
    assert_eq!(
        read_err(&format!("{TRI}VN 0 0 1\n")),
        "t.obj:4: `VN` is not an OBJ statement (OBJ keywords are lower case: did you mean `vn`?): \
         `VN 0 0 1`"
    );
    assert_eq!(
        read_err(&format!("{TRI}fo 1 2 3\n")),
        "t.obj:4: `fo` is the old form of `f`, which this reader does not take: write `f`: \
         `fo 1 2 3`"
    );
    // A long garbage line is cut in the message.
    let junk = "x".repeat(500);
    let e = read_err(&junk);
    assert!(e.len() < 250, "{e}");
}

#[test]
fn face_corners_with_garbage_after_a_slash_are_errors() {
    assert_eq!(
        read_err(&format!("{TRI}f 1 2/x 3\n")),
        "t.obj:4: `2/x` is not a vertex reference: `f 1 2/x 3`"
    );
    assert_eq!(
        read_err(&format!("{TRI}f 1 2/1/1/1 3\n")),
        "t.obj:4: `2/1/1/1` is not a vertex reference: `f 1 2/1/1/1 3`"
    );
    assert_eq!(
        read_err(&format!("{TRI}f 1 2 99999999999999999999\n")),
        "t.obj:4: `99999999999999999999` is not a vertex reference: `f 1 2 99999999999999999999`"
    );
    assert!(read_err(&format!("{TRI}f 1 2 {}\n", i64::MIN)).contains("counts back past"));
}

#[test]
fn a_byte_order_mark_is_skipped() {
    // Once it turned the first `v` into an unknown statement, silently
    // dropping vertex 1; the error then blamed a face.
    let (mesh, warnings) = read(&format!("\u{feff}{TRI}f 1 2 3\n"));
    assert_eq!(mesh.num_vertices(), 3);
    assert!(warnings.is_empty());
    // Anywhere else it is not whitespace: an error on its line.
    let e = read_err(&format!("{TRI}\u{feff}f 1 2 3\n"));
    assert!(
        e.starts_with("t.obj:4: `\u{feff}f` is not an OBJ statement"),
        "{e}"
    );
}

#[test]
fn crlf_line_ends_are_accepted_and_lone_cr_is_refused() {
    let crlf = format!("{TRI}f 1 2 3\n").replace('\n', "\r\n");
    let (mesh, _) = read(&crlf);
    assert_eq!(mesh.num_real_faces(), 1);
    // Errors still count lines right.
    let bad = format!("{TRI}f 1 2 4\n").replace('\n', "\r\n");
    assert!(read_err(&bad).starts_with("t.obj:4: "));
    let cr = format!("{TRI}f 1 2 3\n").replace('\n', "\r");
    assert!(
        read_err(&cr).starts_with("t.obj:1: a carriage return in the middle of a line"),
        "{}",
        read_err(&cr)
    );
}

#[test]
fn a_file_that_is_not_utf8_names_the_line() {
    let dir = std::env::temp_dir().join(format!("halfedge-obj-reader-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("latin1.obj");
    let mut bytes = TRI.as_bytes().to_vec();
    bytes.extend_from_slice(b"# caf\xe9\nf 1 2 3\n");
    std::fs::write(&path, bytes).unwrap();
    let e = Mesh::read_obj_file(&path).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}:4: the file is not UTF-8 text (is it a binary file, or in another encoding?)",
            path.display()
        )
    );
    // The old entry point reads good files as before.
    std::fs::write(&path, format!("{TRI}vn 0 0 1\nf 1 2 3\n")).unwrap();
    assert_eq!(Mesh::from_obj_file(&path).unwrap().num_real_faces(), 1);
    let (_, warnings) = Mesh::read_obj_file(&path).unwrap();
    assert_eq!(warnings[0].path, path.display().to_string());
    std::fs::remove_dir_all(&dir).unwrap();
}
