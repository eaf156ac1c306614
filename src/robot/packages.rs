//! Resolution of mesh filenames: relative paths, `file://` and `package://NAME/...` without ROS.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Where `package://NAME` points: explicit `--package-path NAME=DIR` entries, then a search of the URDF's
/// parent directories for a folder NAME or a `package.xml` declaring NAME.
#[derive(Debug, Clone, Default)]
pub struct PackagePaths {
    explicit: BTreeMap<String, PathBuf>,
}

impl PackagePaths {
    /// No explicit package paths; only the search next to the URDF.
    pub fn new() -> Self {
        Self::default()
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
        let path = if let Some(rest) = uri.strip_prefix("package://") {
            let (name, inner) = rest.split_once('/').unwrap_or((rest, ""));
            self.package_dir(name, base)
                .ok_or_else(|| {
                    format!(
                        "package \"{name}\" not found (searched the URDF's parent folders for a folder \
                         \"{name}\" or a package.xml naming it; add --package-path {name}=DIR)"
                    )
                })?
                .join(inner)
        } else if let Some(rest) = uri.strip_prefix("file://") {
            let p = PathBuf::from(rest);
            if p.is_absolute() { p } else { base.join(p) }
        } else if uri.contains("://") {
            return Err("unsupported URI scheme (use a path, file:// or package://)".into());
        } else {
            base.join(uri)
        };
        if path.is_file() {
            Ok(path)
        } else {
            Err(format!("file not found: {}", path.display()))
        }
    }

    fn package_dir(&self, name: &str, base: &Path) -> Option<PathBuf> {
        if let Some(dir) = self.explicit.get(name) {
            return Some(dir.clone());
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
        None
    }
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
