"""What loads a bearing: ground-motion records and their readers (plain
text, PEER, CSMIP V2, the FEMA P695 sets), the test machine's orbits and its
axial-load programmes. Imports nothing of fpd but itself; the devices'
mechanics (mechanics/) read these (docs/architecture.md, "The layers")."""
