; Solves example.json in 70 time steps (PSW: 115); see README.md for how it was made.
(if-neighbor-on-path-is-free
  (if-on-path-of-robot-in-network
    (if-robot-is-solved
      move-toward-branch
      (if-robot-moving-to-branch move-to-free-neighbor move-toward-objective))
    (if-robot-moving-to-branch move-to-free-neighbor move-toward-objective))
  move-to-free-neighbor)
