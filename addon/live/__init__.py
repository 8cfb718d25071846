"""The live modifier: keeping every entry's result current (engine), through Blender's handlers and timers (handlers),
across renders (render), files (files) and view changes (view), with one state of what the add-on is doing
(activity) and what the artist is told (status)."""
