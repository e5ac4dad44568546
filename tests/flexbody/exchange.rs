//! Reduced-body exchange formats (SID, Matrix Market folder, VTK) and the
//! Exudyn client check (being written).
