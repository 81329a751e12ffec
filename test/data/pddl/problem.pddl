(define (problem toy1) (:domain toy) (:init) (:goal (done)))
