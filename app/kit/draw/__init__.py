"""The 3D pieces: the stage, bodies, line of nodes, vectors and traces (`widgets`), poses sent
only when they change (`lean`), labels laid out without overlap (`labels`) and the screen
projection they use (`screen`).  They import the core, never the panel (`app.kit.panel`)."""
