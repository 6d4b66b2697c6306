//! A small helper to run `spatch` in a temporary folder.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The result of one run.
pub(crate) struct Run {
    pub(crate) code: i32,
    pub(crate) stdout: String,
    pub(crate) stderr: String,
}

impl Run {
    /// Panics with the run's output unless it exited 0.
    pub(crate) fn success(self) -> Self {
        assert_eq!(
            self.code, 0,
            "spatch failed:\nstdout: {}\nstderr: {}",
            self.stdout, self.stderr
        );
        self
    }

    /// Panics unless the run failed as bad input: exit code 2 and one line,
    /// `spatch: error: ...`, naming `file`.
    pub(crate) fn assert_one_clear_line(&self, file: &str) {
        assert_eq!(self.code, 2, "stderr: {}", self.stderr);
        let lines: Vec<&str> = self.stderr.lines().collect();
        assert_eq!(lines.len(), 1, "{}", self.stderr);
        assert!(lines[0].starts_with("spatch: error: "), "{}", lines[0]);
        assert!(lines[0].contains(file), "{}", lines[0]);
    }
}

/// A temporary folder to run `spatch` in.
pub(crate) struct TestCommand {
    dir: tempfile::TempDir,
}

impl TestCommand {
    /// A new empty folder.
    pub(crate) fn new() -> Self {
        Self {
            dir: tempfile::tempdir().expect("temporary folder"),
        }
    }

    /// The JSON file `name` in the folder (a report or statistics),
    /// deserialized as `T` (`serde_json::Value` for untyped access).
    pub(crate) fn json<T: serde::de::DeserializeOwned>(&self, name: &str) -> T {
        serde_json::from_slice(&std::fs::read(self.path(name)).unwrap()).unwrap()
    }

    /// A path inside the folder.
    pub(crate) fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// The folder.
    pub(crate) fn dir(&self) -> &Path {
        self.dir.path()
    }

    /// Runs `spatch` with `args` in the folder, with extra environment.
    pub(crate) fn run_with_env(&self, args: &[&str], env: &[(&str, &str)]) -> Run {
        let mut command = Command::new(env!("CARGO_BIN_EXE_spatch"));
        command.args(args).current_dir(self.dir.path());
        for (k, v) in env {
            command.env(k, v);
        }
        let Output {
            status,
            stdout,
            stderr,
        } = command.output().expect("spatch runs");
        Run {
            code: status.code().unwrap_or(-1),
            stdout: String::from_utf8_lossy(&stdout).into_owned(),
            stderr: String::from_utf8_lossy(&stderr).into_owned(),
        }
    }

    /// Runs `spatch` with `args` in the folder.
    pub(crate) fn run(&self, args: &[&str]) -> Run {
        self.run_with_env(args, &[])
    }

    /// Writes a small sphere file and returns its name.
    pub(crate) fn small_sphere(&self, name: &str) -> String {
        self.sphere(
            name,
            &[
                "--radius",
                "10",
                "--patches",
                "200",
                "--grid",
                "9",
                "--step",
                "0.001",
            ],
        )
    }

    /// Runs `spatch sphere OPTIONS -o NAME`, asserts it succeeded and returns the name.
    pub(crate) fn sphere(&self, name: &str, options: &[&str]) -> String {
        let mut args = vec!["sphere"];
        args.extend_from_slice(options);
        args.extend(["-o", name]);
        self.run(&args).success();
        name.to_owned()
    }
}
