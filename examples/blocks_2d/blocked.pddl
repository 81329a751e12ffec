; b0 into the red region, where b1 stands in the middle leaving no room on either side:
; b1 has to be moved out of the way first.
(define (problem blocks-2d-blocked)
  (:domain blocks-2d)
  (:objects b0 b1 b2 grey red p0 p1 p2 q0)
  (:init (Block b0) (Block b1) (Block b2) (Region grey) (Region red)
         (Placeable b0 grey) (Placeable b0 red) (Placeable b1 grey) (Placeable b1 red)
         (Placeable b2 grey) (Placeable b2 red)
         (Pose b0 p0) (AtPose b0 p0) (Pose b1 p1) (AtPose b1 p1) (Pose b2 p2) (AtPose b2 p2)
         (Conf q0) (AtConf q0) (HandEmpty) (CanMove)
         (= (total-cost) 0))
  (:goal (and (In b0 red) (AtConf q0)))
  (:metric minimize (total-cost)))
