//! `.ci/setup.sh` takes bookworm-backports from the Debian mirror the machine's *active* apt sources
//! use (never a host of its own, a security suite, a third-party repository or a disabled file).

use std::path::{Path, PathBuf};
use std::process::Command;

/// A fake `/etc/apt` with the given files (relative path, content).
fn apt(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("apt_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("sources.list.d")).unwrap();
    for (rel, text) in files {
        std::fs::write(d.join(rel), text).unwrap();
    }
    d
}

/// `setup.sh --print-mirror` against `dir`: (success, stdout, stderr).
fn print_mirror(dir: &Path) -> (bool, String, String) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join(".ci/setup.sh");
    let o = Command::new("bash")
        .arg(script)
        .arg("--print-mirror")
        .env("APT_ETC", dir)
        .output()
        .expect("bash runs");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

const DEBIAN_SOURCES: &str = "Types: deb
URIs: http://mirror.example.net/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: http://security.example.net/debian-security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
";

#[test]
fn deb822_sources_give_the_debian_mirror() {
    let d = apt(
        "deb822",
        &[
            ("sources.list.d/debian.sources", DEBIAN_SOURCES),
            // Disabled by extension: not read.
            (
                "sources.list.d/backports.list.disabled",
                "deb http://other.example.org/debian bookworm-backports main\n",
            ),
        ],
    );
    let (ok, out, err) = print_mirror(&d);
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "http://mirror.example.net/debian\nbackports: not enabled\n"
    );
}

#[test]
fn third_party_commented_and_disabled_entries_are_skipped() {
    let d = apt(
        "mixed",
        &[
            (
                "sources.list",
                "# deb http://commented.example.org/debian bookworm main\n\
                 deb [signed-by=/usr/share/keyrings/docker.gpg] https://download.docker.com/linux/debian bookworm stable\n\
                 deb [arch=amd64 signed-by=/usr/share/keyrings/vendor.gpg] https://vendor.example.com/debian bookworm main\n\
                 deb http://security.example.org/debian-security bookworm-security main\n\
                 deb [arch=amd64] http://local.example.org/debian/ bookworm main contrib\n",
            ),
            (
                "sources.list.d/off.sources",
                "Types: deb\nURIs: http://off.example.org/debian\nSuites: bookworm\nComponents: main\nEnabled: no\n",
            ),
            (
                "sources.list.d/bpo.sources",
                "Types: deb\nURIs: http://local.example.org/debian/\nSuites: bookworm-backports\nComponents: main\n",
            ),
        ],
    );
    let (ok, out, err) = print_mirror(&d);
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "http://local.example.org/debian/\nbackports: enabled\n"
    );
}

#[test]
fn no_debian_source_is_a_clear_error() {
    let d = apt(
        "none",
        &[(
            "sources.list",
            "# deb http://deb.example.org/debian bookworm main\n\
             deb http://security.example.org/debian-security bookworm-security main\n",
        )],
    );
    let (ok, out, err) = print_mirror(&d);
    assert!(!ok && out.is_empty(), "{out}");
    assert!(
        err.contains("no active apt source for Debian bookworm"),
        "{err}"
    );
}

#[test]
fn the_script_names_no_mirror_host() {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(".ci/setup.sh"))
        .unwrap();
    for host in ["deb.debian.org", "debian.org/", "ftp.", "mirror"] {
        let hits: Vec<&str> = text
            .lines()
            .filter(|l| !l.trim_start().starts_with('#') && l.contains(host) && l.contains("http"))
            .collect();
        assert!(hits.is_empty(), "setup.sh names a host ({host}): {hits:?}");
    }
}
