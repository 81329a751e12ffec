(define (problem t2p) (:domain t2) (:objects a b - item) (:init (base a) (base b)) (:goal (done)))
