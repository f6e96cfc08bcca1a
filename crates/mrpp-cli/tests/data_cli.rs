//! `mrpp data get movingai`, offline: a small zip archive built here from the repository's copy
//! of a few benchmark files (their real checksums are in the manifest) is served by an HTTP
//! server on 127.0.0.1 in a thread, or unpacked with --from; the files land byte-identical, a
//! second run is a no-op, and a damaged file fails naming it, with nothing written.

mod common;

use common::{mrpp_exits, root};
use std::io::{BufRead as _, Write as _};
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mrpp-data-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The benchmark files the archives of these tests hold.
const FILES: [&str; 4] = [
    "empty-8-8.map",
    "empty-8-8-random-1.scen",
    "random-32-32-20.map",
    "random-32-32-20-even-2.scen",
];

fn original(name: &str) -> Vec<u8> {
    std::fs::read(root().join("data/movingai").join(name)).unwrap()
}

/// A zip archive of `files` (name in the archive, bytes), deflated, like movingai.com's.
fn zip_of(files: &[(String, Vec<u8>)]) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for (name, bytes) in files {
        zip.start_file(name.as_str(), opts).unwrap();
        zip.write_all(bytes).unwrap();
    }
    zip.finish().unwrap().into_inner()
}

/// Serves `archives` (name, bytes) on 127.0.0.1 from a thread (404 for other paths); returns
/// the base URL. The thread serves until the test process ends.
fn serve(archives: Vec<(String, Vec<u8>)>) -> String {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    std::thread::spawn(move || {
        for stream in listener.incoming() {
            let Ok(mut stream) = stream else { continue };
            let mut reader = std::io::BufReader::new(stream.try_clone().unwrap());
            let mut request = String::new();
            let _ = reader.read_line(&mut request);
            // The headers, up to the empty line.
            let mut line = String::new();
            while reader.read_line(&mut line).is_ok_and(|n| n > 2) {
                line.clear();
            }
            let path = request.split_whitespace().nth(1).unwrap_or("");
            let body = archives
                .iter()
                .find(|(name, _)| path == format!("/{name}"))
                .map(|(_, b)| b.clone());
            let head = match &body {
                Some(b) => format!(
                    "HTTP/1.1 200 OK\r\nContent-Length: {}\r\nContent-Type: application/zip\r\nConnection: close\r\n\r\n",
                    b.len()
                ),
                None => "HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
                    .to_string(),
            };
            let _ = stream.write_all(head.as_bytes());
            let _ = stream.write_all(&body.unwrap_or_default());
        }
    });
    format!("http://127.0.0.1:{port}/")
}

/// The three archives of a download, holding FILES in the folders movingai.com's use.
fn archives(damage: Option<&str>) -> Vec<(String, Vec<u8>)> {
    let entry = |folder: &str, name: &str| {
        let mut bytes = original(name);
        if damage == Some(name) {
            let middle = bytes.len() / 2;
            bytes[middle] ^= 1;
        }
        (format!("{folder}/{name}"), bytes)
    };
    vec![
        (
            "mapf-map.zip".into(),
            zip_of(&[entry("mapf-map", FILES[0]), entry("mapf-map", FILES[2])]),
        ),
        (
            "mapf-scen-random.zip".into(),
            zip_of(&[entry("scen-random", FILES[1])]),
        ),
        (
            "mapf-scen-even.zip".into(),
            zip_of(&[entry("scen-even", FILES[3])]),
        ),
    ]
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

/// A download from the local server: every file lands byte-identical (and nothing else), the
/// second run writes nothing; a differing existing file is an error naming it, `--force`
/// replaces it.
#[test]
fn download_from_a_local_server() {
    let url = serve(archives(None));
    let into = tmp("download").join("movingai");
    let into_s = into.to_str().unwrap();
    let (out, _) = mrpp_exits(
        &["data", "get", "movingai", "--url", &url, "--into", into_s],
        0,
    );
    assert!(out.contains("4 file(s) written"), "{out}");
    let mut expected: Vec<String> = FILES.iter().map(|s| s.to_string()).collect();
    expected.sort();
    assert_eq!(files_in(&into), expected);
    for name in FILES {
        assert_eq!(
            std::fs::read(into.join(name)).unwrap(),
            original(name),
            "{name}"
        );
    }
    let (out, _) = mrpp_exits(
        &["data", "get", "movingai", "--url", &url, "--into", into_s],
        0,
    );
    assert!(out.contains("0 file(s) written, 4 already there"), "{out}");

    // A file that differs from the archive's is not replaced silently.
    std::fs::write(into.join(FILES[1]), "changed").unwrap();
    let (_, err) = mrpp_exits(
        &["data", "get", "movingai", "--url", &url, "--into", into_s],
        1,
    );
    assert!(err.contains(FILES[1]) && err.contains("--force"), "{err}");
    assert_eq!(std::fs::read(into.join(FILES[1])).unwrap(), b"changed");
    mrpp_exits(
        &[
            "data", "get", "movingai", "--url", &url, "--into", into_s, "--force",
        ],
        0,
    );
    assert_eq!(
        std::fs::read(into.join(FILES[1])).unwrap(),
        original(FILES[1])
    );
}

/// A damaged file (checksum mismatch) fails with exit 1 naming the archive and the file, and
/// nothing at all is written (not even the good files); a bad zip and a server without the
/// archives fail naming the archive, the latter with the hint to use --from.
#[test]
fn damaged_archives_write_nothing() {
    let url = serve(archives(Some("random-32-32-20-even-2.scen")));
    let into = tmp("damaged").join("movingai");
    let into_s = into.to_str().unwrap();
    let (_, err) = mrpp_exits(
        &["data", "get", "movingai", "--url", &url, "--into", into_s],
        1,
    );
    assert!(
        err.contains("mapf-scen-even.zip: scen-even/random-32-32-20-even-2.scen")
            && err.contains("checksum mismatch"),
        "{err}"
    );
    assert!(!into.exists(), "{:?}", files_in(&into));

    let mut bad = archives(None);
    bad[1].1.truncate(100);
    let (_, err) = mrpp_exits(
        &[
            "data",
            "get",
            "movingai",
            "--url",
            &serve(bad),
            "--into",
            into_s,
        ],
        1,
    );
    assert!(
        err.contains("mapf-scen-random.zip") && err.contains("not a readable zip"),
        "{err}"
    );
    assert!(!into.exists());

    let (_, err) = mrpp_exits(
        &[
            "data",
            "get",
            "movingai",
            "--url",
            &serve(Vec::new()),
            "--into",
            into_s,
        ],
        1,
    );
    assert!(
        err.contains("mapf-map.zip") && err.contains("cannot download") && err.contains("--from"),
        "{err}"
    );
}

/// `--from` a local zip and a folder; a file the manifest does not name is skipped with a
/// warning.
#[test]
fn from_local_archives_and_folders() {
    let dir = tmp("from");
    let archive = dir.join("mine.zip");
    let mut files: Vec<(String, Vec<u8>)> = FILES[..2]
        .iter()
        .map(|n| (format!("some/folder/{n}"), original(n)))
        .collect();
    files.push(("notes/not-a-benchmark.scen".into(), b"version 1\n".to_vec()));
    std::fs::write(&archive, zip_of(&files)).unwrap();
    let folder = dir.join("folder");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(folder.join(FILES[2]), original(FILES[2])).unwrap();
    let into = dir.join("movingai");
    let (out, err) = mrpp_exits(
        &[
            "data",
            "get",
            "movingai",
            "--from",
            archive.to_str().unwrap(),
            "--from",
            folder.to_str().unwrap(),
            "--into",
            into.to_str().unwrap(),
        ],
        0,
    );
    assert!(out.contains("3 file(s) written"), "{out}");
    assert!(
        err.contains("notes/not-a-benchmark.scen") && err.contains("skipped"),
        "{err}"
    );
    for name in &FILES[..3] {
        assert_eq!(std::fs::read(into.join(name)).unwrap(), original(name));
    }
    assert_eq!(files_in(&into).len(), 3);

    // Not a zip at all.
    let junk = dir.join("junk.zip");
    std::fs::write(&junk, b"not a zip").unwrap();
    let (_, err) = mrpp_exits(
        &[
            "data",
            "get",
            "movingai",
            "--from",
            junk.to_str().unwrap(),
            "--into",
            into.to_str().unwrap(),
        ],
        1,
    );
    assert!(
        err.contains("junk.zip") && err.contains("not a readable zip"),
        "{err}"
    );
}

/// `--progress plain` reports each stage of an unpacking in plain lines on stderr (archive
/// entries unpacked, files verified, files written); the default (stderr not a terminal) and
/// `--quiet` print none.
#[test]
fn plain_progress_reports_unpacking_verifying_and_writing() {
    let dir = tmp("progress");
    let archive = dir.join("mine.zip");
    let files: Vec<(String, Vec<u8>)> = FILES[..3]
        .iter()
        .map(|n| (format!("some/folder/{n}"), original(n)))
        .collect();
    std::fs::write(&archive, zip_of(&files)).unwrap();
    let get = |into: &str, extra: &[&str]| {
        let into = dir.join(into);
        let mut args = vec![
            "data",
            "get",
            "movingai",
            "--from",
            archive.to_str().unwrap(),
            "--into",
            into.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        mrpp_exits(&args, 0)
    };
    let (out, err) = get("plain", &["--progress", "plain"]);
    assert!(out.contains("3 file(s) written"), "{out}");
    for line in [
        "unpack mine.zip: 3/3 entries",
        "verify: 3/3 files",
        "write: 3/3 files",
    ] {
        assert!(
            err.lines().any(|l| l.starts_with('[') && l.ends_with(line)),
            "no `{line}` line: {err}"
        );
    }
    // A second run writes nothing: no write stage.
    let (_, err) = get("plain", &["--progress", "plain"]);
    assert!(
        err.contains("verify: 3/3 files") && !err.contains("write:"),
        "{err}"
    );
    let (_, err) = get("auto", &[]);
    assert!(err.is_empty(), "{err}");
    let (_, err) = get("quiet", &["--progress", "plain", "--quiet"]);
    assert!(err.is_empty(), "{err}");
}
