(define (problem t1p) (:domain t1) (:init) (:goal (q)))
