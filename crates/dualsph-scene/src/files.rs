//! Reading the files a scene's generators name (STL meshes and polygon outlines of shapes,
//! particle files of `File` generators), relative to the scene file's directory.

use crate::error::Problem;
use crate::particles_file;
use crate::schema::Generator;
use crate::shapes::{self, Region};
use std::path::Path;

/// Reads the files of `particles` (generator shapes, cut regions and `File` generators) in a
/// `d`-dimensional scene whose file is in `dir`. Shapes of another dimension are left unread
/// (validation refuses them by their dimension).
pub(crate) fn load(particles: &mut [Generator], dir: &Path, d: usize) -> Result<(), Problem> {
    for (i, g) in particles.iter_mut().enumerate() {
        if let Generator::Shape(s) = g {
            shapes::load_shape(&format!("particles[{i}].shape"), &mut s.shape, dir, d)?;
        }
        for (j, cut) in g.cut_mut().iter_mut().enumerate() {
            if let Region::Shape(s) = cut {
                shapes::load_shape(&format!("particles[{i}].cut[{j}]"), s, dir, d)?;
            }
        }
    }
    for (i, g) in particles.iter_mut().enumerate() {
        if let Generator::File(f) = g {
            particles_file::read(i, f, dir, d)?;
        }
    }
    Ok(())
}
