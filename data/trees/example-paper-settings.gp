; mrpp GP program (Trudeau & Clark decision tree): 95 nodes, depth 16
(if-neighbor-on-path-is-free
  (if-on-path-of-robot-in-network
    (if-on-path-of-robot-in-network
      move-toward-objective
      (if-two-robots-on-each-others-path move-toward-branch move-to-free-neighbor))
    (if-on-path-of-robot-in-network
      move-to-free-neighbor
      (if-robot-moving-to-branch move-to-free-neighbor move-toward-objective)))
  (if-on-path-of-robot-in-network
    (if-robot-at-destination
      (if-on-path-of-robot-in-network
        move-to-free-neighbor
        (if-robot-in-network-moving-to-branch
          (if-robot-at-branch
            (if-robot-moving-to-branch
              move-to-free-neighbor
              (if-neighbor-on-path-is-free
                move-to-free-neighbor
                (if-robot-is-solved
                  (if-neighbor-is-surrounded
                    move-toward-branch
                    (if-on-path-of-robot-in-network move-to-free-neighbor move-to-free-neighbor))
                  (if-robot-in-network-moving-to-branch
                    (if-robot-is-solved
                      (if-robot-moving-to-branch
                        move-toward-objective
                        (if-on-path-of-robot-in-network
                          (if-robot-in-network-moving-to-branch
                            move-toward-objective
                            (if-neighbor-is-surrounded
                              move-to-free-neighbor
                              move-toward-objective))
                          (if-robot-moving-to-branch
                            (if-robot-in-network-moving-to-branch
                              (if-robot-at-branch move-to-free-neighbor stay)
                              (if-robot-at-branch move-toward-branch move-to-free-neighbor))
                            (if-neighbor-on-path-is-free
                              move-toward-branch
                              move-to-free-neighbor))))
                      move-toward-objective)
                    move-toward-objective))))
            (if-robot-moving-to-branch move-toward-objective move-to-free-neighbor))
          move-toward-branch))
      (if-robot-in-network-moving-to-branch
        move-to-free-neighbor
        (if-neighbor-is-surrounded
          (if-neighbor-is-surrounded move-to-free-neighbor move-to-free-neighbor)
          move-toward-branch)))
    (if-two-robots-on-each-others-path
      move-to-free-neighbor
      (if-robot-is-solved
        (if-robot-at-destination
          (if-on-path-of-robot-in-network
            move-to-free-neighbor
            (if-robot-at-destination
              (if-on-path-of-robot-in-network
                stay
                (if-on-path-of-robot-in-network
                  (if-robot-in-network-moving-to-branch
                    move-toward-branch
                    move-toward-objective)
                  (if-robot-moving-to-branch
                    (if-robot-in-network-moving-to-branch
                      move-toward-objective
                      move-toward-objective)
                    (if-robot-in-network-moving-to-branch
                      move-toward-branch
                      move-toward-objective))))
              (if-robot-is-solved move-toward-objective stay)))
          (if-robot-in-network-moving-to-branch stay move-toward-branch))
        (if-neighbor-on-path-is-free
          (if-on-path-of-robot-in-network
            move-toward-objective
            (if-robot-moving-to-branch move-to-free-neighbor move-toward-branch))
          move-to-free-neighbor)))))
