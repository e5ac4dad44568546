//! Cross-check against CalculiX: assembled K, M and frequencies of small
//! decks against ccx fixtures (being written).
