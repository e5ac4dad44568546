//! FE matrices from other programs (Matrix Market, CalculiX `.sti`/`.mas`/`.dof`): being written.
