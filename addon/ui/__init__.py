"""What the artist sees: the settings (properties), the operators and menus (operators) and the panel (panel)."""
