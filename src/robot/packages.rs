//! Resolution of mesh filenames: relative paths, `file://`, `package://NAME/...` and `model://NAME/...`.
//!
//! `package://NAME` is looked up, in this order, in the explicit `--package-path NAME=DIR` entries, in
//! `ROS_PACKAGE_PATH` (ROS 1: each folder and the folders below it, for a `package.xml` naming NAME),
//! in `AMENT_PREFIX_PATH` (ROS 2: `PREFIX/share/NAME`), and last in the URDF's parent folders (a folder
//! NAME, a `package.xml` naming NAME, or a subfolder NAME). `model://NAME` is looked up in the explicit
//! entries, `GZ_SIM_RESOURCE_PATH`, `IGN_GAZEBO_RESOURCE_PATH` and `GAZEBO_MODEL_PATH` (`DIR/NAME`), then
//! the URDF's parent folders. The environment is read only when asked ([`PackagePaths::from_env`]).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// How deep below a `ROS_PACKAGE_PATH` entry packages are searched (rospack crawls without a limit; a
/// workspace's packages sit a few folders down).
const CRAWL_DEPTH: usize = 6;

/// The environment variables that list package folders, by scheme.
const ROS_VARS: [&str; 2] = ["ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH"];
const MODEL_VARS: [&str; 3] = [
    "GZ_SIM_RESOURCE_PATH",
    "IGN_GAZEBO_RESOURCE_PATH",
    "GAZEBO_MODEL_PATH",
];

/// Where `package://NAME` and `model://NAME` point.
#[derive(Debug, Clone, Default)]
pub struct PackagePaths {
    explicit: BTreeMap<String, PathBuf>,
    /// Environment variables that list folders (name, folders in order).
    env: Vec<(&'static str, Vec<PathBuf>)>,
}

impl PackagePaths {
    /// No explicit package paths and no environment; only the search next to the URDF.
    pub fn new() -> Self {
        Self::default()
    }

    /// The ROS and Gazebo variables of this process's environment (unset ones are remembered as such,
    /// for the error message).
    pub fn from_env() -> Self {
        let mut paths = Self::new();
        for var in ROS_VARS.iter().chain(&MODEL_VARS) {
            let dirs = std::env::var_os(var)
                .map(|v| {
                    std::env::split_paths(&v)
                        .filter(|p| !p.as_os_str().is_empty())
                        .collect()
                })
                .unwrap_or_default();
            paths.env.push((var, dirs));
        }
        paths
    }

    /// Sets the folders an environment variable lists (as [`PackagePaths::from_env`] reads them).
    pub fn set_env(&mut self, var: &'static str, dirs: Vec<PathBuf>) {
        self.env.retain(|(v, _)| *v != var);
        self.env.push((var, dirs));
    }

    /// Adds `NAME=DIR`.
    pub fn insert(&mut self, name: impl Into<String>, dir: impl Into<PathBuf>) {
        self.explicit.insert(name.into(), dir.into());
    }

    /// Parses a `NAME=DIR` command-line value.
    pub fn parse_entry(entry: &str) -> Option<(String, PathBuf)> {
        let (name, dir) = entry.split_once('=')?;
        (!name.is_empty() && !dir.is_empty()).then(|| (name.to_string(), PathBuf::from(dir)))
    }

    /// Resolves a mesh `uri` written in the URDF at `urdf`. The error says what was tried.
    pub fn resolve(&self, uri: &str, urdf: &Path) -> Result<PathBuf, String> {
        let base = urdf.parent().unwrap_or(Path::new("."));
        let scheme = [("package://", Scheme::Package), ("model://", Scheme::Model)]
            .into_iter()
            .find_map(|(prefix, s)| uri.strip_prefix(prefix).map(|rest| (s, rest)));
        let path = if let Some((scheme, rest)) = scheme {
            let (name, inner) = rest.split_once('/').unwrap_or((rest, ""));
            let mut searched = Vec::new();
            self.package_dir(scheme, name, base, &mut searched)
                .ok_or_else(|| {
                    format!(
                        "{} \"{name}\" not found; searched {}; add --package-path {name}=DIR",
                        scheme.noun(),
                        searched.join(", ")
                    )
                })?
                .join(inner)
        } else if let Some(rest) = uri.strip_prefix("file://") {
            let p = PathBuf::from(rest);
            if p.is_absolute() { p } else { base.join(p) }
        } else if uri.contains("://") {
            return Err(
                "unsupported URI scheme (use a path, file://, package:// or model://)".into(),
            );
        } else {
            base.join(uri)
        };
        match std::fs::metadata(&path) {
            Ok(m) if m.is_file() => Ok(path),
            Ok(m) if m.is_dir() => Err(format!("{} is a folder, not a mesh file", path.display())),
            Ok(_) => Err(format!("{} is not a regular file", path.display())),
            Err(_) => Err(format!("file not found: {}", path.display())),
        }
    }

    /// The folder of package (or model) `name`; `searched` collects every place looked at.
    fn package_dir(
        &self,
        scheme: Scheme,
        name: &str,
        base: &Path,
        searched: &mut Vec<String>,
    ) -> Option<PathBuf> {
        if let Some(dir) = self.explicit.get(name) {
            return Some(dir.clone());
        }
        searched.push(if self.explicit.is_empty() {
            "--package-path (none given)".to_string()
        } else {
            format!(
                "--package-path ({} only)",
                self.explicit.keys().cloned().collect::<Vec<_>>().join(", ")
            )
        });
        let vars: &[&str] = match scheme {
            Scheme::Package => &ROS_VARS,
            Scheme::Model => &MODEL_VARS,
        };
        for var in vars {
            let Some((_, dirs)) = self.env.iter().find(|(v, _)| v == var) else {
                continue;
            };
            if dirs.is_empty() {
                searched.push(format!("{var} (unset)"));
                continue;
            }
            for dir in dirs {
                let found = match *var {
                    "ROS_PACKAGE_PATH" => crawl_for_package(dir, name, CRAWL_DEPTH),
                    "AMENT_PREFIX_PATH" => {
                        Some(dir.join("share").join(name)).filter(|d| d.is_dir())
                    }
                    _ => Some(dir.join(name)).filter(|d| d.is_dir()),
                };
                if found.is_some() {
                    return found;
                }
            }
            let shown: Vec<String> = dirs
                .iter()
                .map(|d| match *var {
                    "AMENT_PREFIX_PATH" => d.join("share").join(name).display().to_string(),
                    "ROS_PACKAGE_PATH" => format!("{} and below", d.display()),
                    _ => d.join(name).display().to_string(),
                })
                .collect();
            searched.push(format!("{var} ({})", shown.join(", ")));
        }
        let base = std::path::absolute(base).unwrap_or_else(|_| base.to_path_buf());
        for dir in base.ancestors() {
            if dir.file_name().is_some_and(|n| n == name) {
                return Some(dir.to_path_buf());
            }
            if declares_package(&dir.join("package.xml"), name) {
                return Some(dir.to_path_buf());
            }
            let sub = dir.join(name);
            if sub.is_dir() {
                return Some(sub);
            }
        }
        searched.push(format!(
            "the URDF's parent folders ({} and up, for a folder \"{name}\" or a package.xml naming it)",
            base.display()
        ));
        None
    }
}

/// The two URI schemes that name a package-like folder.
#[derive(Debug, Clone, Copy)]
enum Scheme {
    Package,
    Model,
}

impl Scheme {
    fn noun(self) -> &'static str {
        match self {
            Scheme::Package => "package",
            Scheme::Model => "model",
        }
    }
}

/// rospack's crawl: `dir` itself or a folder below it whose `package.xml` names `name`; a folder with a
/// `package.xml` is not descended into, nor one holding `CATKIN_IGNORE`.
fn crawl_for_package(dir: &Path, name: &str, depth: usize) -> Option<PathBuf> {
    let manifest = dir.join("package.xml");
    if manifest.is_file() {
        return declares_package(&manifest, name).then(|| dir.to_path_buf());
    }
    if depth == 0 || dir.join("CATKIN_IGNORE").exists() {
        return None;
    }
    let mut subdirs: Vec<PathBuf> = std::fs::read_dir(dir)
        .ok()?
        .filter_map(|e| e.ok())
        .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
        .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
        .map(|e| e.path())
        .collect();
    subdirs.sort();
    subdirs
        .iter()
        .find_map(|d| crawl_for_package(d, name, depth - 1))
}

/// Whether the `package.xml` at `path` exists and declares `<name>NAME</name>`.
fn declares_package(path: &Path, name: &str) -> bool {
    let Ok(text) = std::fs::read_to_string(path) else {
        return false;
    };
    let Ok(doc) = roxmltree::Document::parse(&text) else {
        return false;
    };
    doc.root_element()
        .children()
        .any(|c| c.tag_name().name() == "name" && c.text().map(str::trim) == Some(name))
}
