//! Abaqus/CalculiX input decks (`.inp`): being written.
